// The real SH basis: orthonormal over the sphere, the documented constants, and the GLSL
// twin (shaders/common_sh.glsl, evaluated by RainRenderer) equal to shEvaluate().
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "gpu/rain_renderer.h"

namespace pluvia::gpu {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(ShBasis, IsOrthonormalOverTheSphere) {
  // Midpoint rule in z = cos(theta) and in phi: dA = dz dphi is exact area measure, and the
  // integrands are polynomials of degree <= 6, so 256 x 512 cells leave ~1e-5 error.
  constexpr int kZSteps = 256, kPhiSteps = 512;
  const double cellArea = (2.0 / kZSteps) * (2.0 * kPi / kPhiSteps);
  double gram[16][16] = {};
  for (int iz = 0; iz < kZSteps; ++iz) {
    const double z = -1.0 + (iz + 0.5) * 2.0 / kZSteps;
    const double r = std::sqrt(1.0 - z * z);
    for (int ip = 0; ip < kPhiSteps; ++ip) {
      const double phi = (ip + 0.5) * 2.0 * kPi / kPhiSteps;
      const auto y = rain::shEvaluate(static_cast<float>(r * std::cos(phi)),
                                      static_cast<float>(r * std::sin(phi)), static_cast<float>(z));
      for (int i = 0; i < 16; ++i) {
        for (int j = 0; j < 16; ++j) gram[i][j] += double(y[i]) * y[j] * cellArea;
      }
    }
  }
  for (int i = 0; i < 16; ++i) {
    for (int j = 0; j < 16; ++j) {
      EXPECT_NEAR(gram[i][j], i == j ? 1.0 : 0.0, 1e-3) << "Y" << i << " . Y" << j;
    }
  }
}

TEST(ShBasis, MatchesTheDocumentedFormulas) {
  const float x = 0.36f, y = -0.48f, z = 0.8f;  // unit length
  const auto b = rain::shEvaluate(x, y, z);
  const double expected[16] = {0.282095,
                               0.488603 * y,
                               0.488603 * z,
                               0.488603 * x,
                               1.092548 * x * y,
                               1.092548 * y * z,
                               0.315392 * (3 * z * z - 1),
                               1.092548 * x * z,
                               0.546274 * (x * x - y * y),
                               0.590044 * y * (3 * x * x - y * y),
                               2.890611 * x * y * z,
                               0.457046 * y * (5 * z * z - 1),
                               0.373176 * z * (5 * z * z - 3),
                               0.457046 * x * (5 * z * z - 1),
                               1.445306 * z * (x * x - y * y),
                               0.590044 * x * (x * x - 3 * y * y)};
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(b[i], expected[i], 2e-6) << "Y" << i;
}

TEST(ShBasis, BandEnergyIsRotationInvariant) {
  // Addition theorem: sum_m Y_lm(d)^2 = (2l + 1) / (4 pi) for every unit d.
  std::mt19937 random(7);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 50; ++trial) {
    double v[3] = {normal(random), normal(random), normal(random)};
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    const auto b = rain::shEvaluate(float(v[0] / n), float(v[1] / n), float(v[2] / n));
    for (int l = 0; l <= 3; ++l) {
      double energy = 0;
      for (int m = -l; m <= l; ++m) energy += double(b[l * l + l + m]) * b[l * l + l + m];
      EXPECT_NEAR(energy, (2 * l + 1) / (4 * kPi), 1e-5) << "band " << l;
    }
  }
}

// Renders still drops (widthPx x widthPx squares) with matte 1 over a black background and
// c = 0, so each square's composite is C = max(sum_i env_i Y_i(view), 0) per channel. With
// env one-hot at i holding (1, -1, 0), R - G = Y_i(view) as the vertex shader computed it.
TEST(ShBasis, GlslBasisEqualsShEvaluate) {
  constexpr int kSize = 32, kGrid = 6, kCell = kSize / kGrid;  // 36 drops, 5 px apart
  std::mt19937 random(11);
  std::normal_distribution<float> normal;
  std::vector<rain::StreakInstance> drops;
  std::vector<std::array<float, 3>> views;
  for (int k = 0; k < kGrid * kGrid; ++k) {
    float v[3] = {normal(random), normal(random), normal(random)};
    if (k < 6) {  // the six axis directions first
      v[0] = v[1] = v[2] = 0.0f;
      v[k / 2] = k % 2 ? -1.0f : 1.0f;
    }
    const float n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    views.push_back({v[0] / n, v[1] / n, v[2] / n});
    const float cx = (k % kGrid) * kCell + 2.5f, cy = (k / kGrid) * kCell + 2.5f;
    drops.push_back({cx, cy, cx, cy, 3.0f, 1.0f, 1.0f, 0.0f, views.back()[0], views.back()[1],
                     views.back()[2], 0.0f});
  }
  RainRenderer renderer(kSize, kSize);
  renderer.setStrokeAtlas({2, 2, {1, 1, 1, 1}, {{0, 0, 2, 2}}});
  for (int i = 0; i < 16; ++i) {
    rain::ShadingParams shading;
    shading.shOrder = 3;
    shading.envSh.assign(16, {0, 0, 0});
    shading.envSh[i] = {1.0f, -1.0f, 0.0f};
    shading.transferZonal = {1, 1, 1, 1};
    shading.backgroundWeight = 0.0f;
    Image frame(kSize, kSize);
    renderer.render(frame, drops, shading);
    for (size_t k = 0; k < drops.size(); ++k) {
      const float* p =
          frame.pixel(static_cast<int>(drops[k].headX), static_cast<int>(drops[k].headY));
      const float expected = rain::shEvaluate(views[k][0], views[k][1], views[k][2])[i];
      EXPECT_NEAR(p[0] - p[1], expected, 1e-5f) << "Y" << i << " at drop " << k;
    }
  }
}

}  // namespace
}  // namespace pluvia::gpu
