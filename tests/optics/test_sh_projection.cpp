// Real spherical harmonics of any order (optics/sh.h): orthonormality under the equirect
// projection, equality with the GPU's order-3 basis, the addition theorem behind the closed-form
// rotation, the white furnace through the zonal transfer, the paper's precomputed rotation table
// against the closed form, and the windowing that tames the ringing around a sun.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "image/equirect.h"
#include "lab/optics_report.h"
#include "lab/test_environment.h"
#include "optics/drop_transfer.h"
#include "optics/paper_transfer_table.h"
#include "optics/sh.h"
#include "rain/streak_types.h"
#include "test_support.h"

namespace pluvia::optics {
namespace {

using Vec = std::array<double, 3>;

int shIndex(int l, int m) {
  return l * l + l + m;
}

double dot(const Vec& a, const Vec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Uniformly distributed unit vectors (normalised Gaussians), reproducible.
std::vector<Vec> randomDirections(int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<Vec> out;
  while (int(out.size()) < count) {
    Vec v = {normal(rng), normal(rng), normal(rng)};
    const double n = std::sqrt(dot(v, v));
    if (n < 1e-6) continue;
    out.push_back({v[0] / n, v[1] / n, v[2] / n});
  }
  return out;
}

// Legendre polynomial P_l(x) by Bonnet's recurrence, independent of sh.cpp.
double legendre(int l, double x) {
  double previous = 1.0, current = x;
  if (l == 0) return previous;
  for (int k = 1; k < l; ++k) {
    const double next = ((2.0 * k + 1.0) * x * current - k * previous) / (k + 1.0);
    previous = current;
    current = next;
  }
  return current;
}

TEST(ShProjection, BasisIsOrthonormalUnderTheEquirectProjection) {
  // Each channel of a 512 x 256 map holds one Y_lm at the texel centres; its projection must be
  // the unit vector at (l, m). The projection is a midpoint rule over texels (exact solid
  // angles, the integrand sampled at centres): exact in phi for these trigonometric
  // polynomials, its error in theta grows like (l * texel angle)^2 / 24, at most 4e-4 at l = 8
  // for a texel of pi / 256 rad (measured: 3e-5), hence the tolerance 1e-3. A wrong
  // normalisation, sign or index moves an entry by far more.
  constexpr int kOrder = 8, kWidth = 512, kHeight = 256;
  constexpr double kTolerance = 1e-3;
  const std::vector<std::array<std::array<int, 2>, 3>> cases = {
      {{{0, 0}, {1, -1}, {1, 1}}},
      {{{2, 1}, {2, -2}, {3, -3}}},
      {{{4, 0}, {5, 2}, {6, -5}}},
      {{{7, 7}, {8, 0}, {8, -8}}},
  };
  std::vector<double> basis;
  for (const auto& three : cases) {
    const EquirectMap map = test::equirectOf(kWidth, kHeight, [&](const Vec& d) {
      shBasis(kOrder, d, basis);
      Vec v;
      for (size_t c = 0; c < 3; ++c) v[c] = basis[size_t(shIndex(three[c][0], three[c][1]))];
      return v;
    });
    const ShCoefficients projected = projectEnvironment(map, kOrder);
    ASSERT_EQ(projected.size(), size_t((kOrder + 1) * (kOrder + 1)));
    double worst = 0.0;
    for (size_t c = 0; c < 3; ++c) {
      const int target = shIndex(three[c][0], three[c][1]);
      for (int i = 0; i < int(projected.size()); ++i) {
        const double expected = i == target ? 1.0 : 0.0;
        worst = std::max(worst, std::abs(projected[size_t(i)][c] - expected));
        EXPECT_NEAR(projected[size_t(i)][c], expected, kTolerance)
            << "projection of Y(" << three[c][0] << "," << three[c][1] << ") onto index " << i;
      }
    }
    std::cout << "orthonormality: largest deviation " << worst << " for Y(" << three[0][0] << ","
              << three[0][1] << "), Y(" << three[1][0] << "," << three[1][1] << "), Y("
              << three[2][0] << "," << three[2][1] << ")\n";
  }
}

TEST(ShProjection, MatchesTheGpuBasisUpToOrderThree) {
  // shEvaluate works in float: values of order 1 carry ~1e-7 rounding, so 1e-6 is tight yet
  // far below any wrong constant, sign or index (those differ by > 1e-2).
  std::vector<double> basis;
  for (const Vec& d : randomDirections(500, 7)) {
    const float x = float(d[0]), y = float(d[1]), z = float(d[2]);
    const std::array<float, 16> gpuBasis = rain::shEvaluate(x, y, z);
    shBasis(3, {double(x), double(y), double(z)}, basis);
    ASSERT_EQ(basis.size(), 16u);
    for (size_t i = 0; i < 16; ++i) {
      ASSERT_NEAR(basis[i], double(gpuBasis[i]), 1e-6)
          << "index " << i << " at " << x << "," << y << "," << z;
    }
  }
}

TEST(ShProjection, AdditionTheoremHoldsForEveryBandUpToEight) {
  // sum_m Y_lm(a) Y_lm(b) = (2l + 1) / (4 pi) P_l(a . b): the identity the closed-form rotation
  // (shadeZonal, rotatedTransfer) rests on. Both sides are sums of a few O(1) terms in double,
  // so 1e-9 leaves room only for rounding.
  constexpr int kOrder = 8;
  const std::vector<Vec> a = randomDirections(200, 11), b = randomDirections(200, 12);
  std::vector<double> ya, yb;
  for (size_t k = 0; k < a.size(); ++k) {
    shBasis(kOrder, a[k], ya);
    shBasis(kOrder, b[k], yb);
    for (int l = 0; l <= kOrder; ++l) {
      double sum = 0.0;
      for (int m = -l; m <= l; ++m) sum += ya[size_t(shIndex(l, m))] * yb[size_t(shIndex(l, m))];
      const double expected = (2.0 * l + 1.0) / (4.0 * M_PI) * legendre(l, dot(a[k], b[k]));
      ASSERT_NEAR(sum, expected, 1e-9) << "l = " << l << ", pair " << k;
    }
    // a = b: sum_m Y_lm(a)^2 = (2l + 1) / (4 pi), the normalisation of each band.
    for (int l = 0; l <= kOrder; ++l) {
      double sum = 0.0;
      for (int m = -l; m <= l; ++m) sum += ya[size_t(shIndex(l, m))] * ya[size_t(shIndex(l, m))];
      ASSERT_NEAR(sum, (2.0 * l + 1.0) / (4.0 * M_PI), 1e-9) << "l = " << l;
    }
  }
}

TEST(ShProjection, WhiteFurnaceThroughTheZonalTransfer) {
  // A uniform environment has only L_00 = sqrt(4 pi) L; the rotated transfer then gives
  // sqrt(4 pi) d_0 Y_00 L_00 = (transfer energy) * L for every view. The bands l > 0 of the
  // projection are not exactly 0 (midpoint rule in theta, ~1e-4 of L_00 at 512 x 256), hence
  // 1e-3 relative.
  const Vec radiance = {0.5, 1.0, 2.0};
  const EquirectMap uniform = uniformEquirect(512, 256, {0.5f, 1.0f, 2.0f});
  const ShCoefficients environment = projectEnvironment(uniform, 8);
  const std::vector<Vec> views = randomDirections(40, 21);
  for (int terms : {1, 9, 20}) {
    const DropOptics optics{1.333, terms};
    const double energy = transferEnergy(optics);
    for (int order : {0, 3, 8}) {
      const std::vector<double> zonal = transferZonal(optics, order);
      ASSERT_EQ(zonal.size(), size_t(order + 1));
      const ShCoefficients truncated(environment.begin(),
                                     environment.begin() + (order + 1) * (order + 1));
      for (const Vec& v : views) {
        const auto c = shadeZonal(truncated, {zonal, zonal, zonal}, v);
        for (size_t k = 0; k < 3; ++k) {
          ASSERT_NEAR(c[k], radiance[k] * energy, 1e-3 * radiance[k] * energy)
              << "N = " << terms << ", L = " << order << ", channel " << k;
        }
      }
      // The same through the full order-8 environment: shadeZonal uses min(order, env order).
      for (const Vec& v : views) {
        const auto c = shadeZonal(environment, {zonal, zonal, zonal}, v);
        EXPECT_NEAR(c[1], energy, 1e-3 * energy) << "N = " << terms << ", L = " << order;
      }
    }
  }
}

// The texel centres of any 6 x n x n cube map: one coordinate +-1, the other two on the grid
// (2 (i + 0.5) / n - 1), normalised. The grid is symmetric under negation, so the set does not
// depend on how the faces are oriented.
std::vector<Vec> cubeTexelCentres(int n, int stride) {
  std::vector<Vec> out;
  for (int axis = 0; axis < 3; ++axis) {
    for (double sign : {1.0, -1.0}) {
      for (int j = 0; j < n; j += stride) {
        for (int i = 0; i < n; i += stride) {
          Vec d;
          d[size_t(axis)] = sign;
          d[size_t((axis + 1) % 3)] = 2.0 * (i + 0.5) / n - 1.0;
          d[size_t((axis + 2) % 3)] = 2.0 * (j + 0.5) / n - 1.0;
          const double length = std::sqrt(dot(d, d));
          out.push_back({d[0] / length, d[1] / length, d[2] / length});
        }
      }
    }
  }
  return out;
}

TEST(ShProjection, PaperTransferTableAgreesWithTheClosedFormRotation) {
  const std::array<std::vector<double>, 3> zonal = {transferZonal(DropOptics{1.331, 9}, 3),
                                                    transferZonal(DropOptics{1.333, 9}, 3),
                                                    transferZonal(DropOptics{1.338, 9}, 3)};
  const PaperTransferTable table(zonal);
  EXPECT_EQ(table.directions(), 98304);
  EXPECT_EQ(table.bytes(), size_t(98304) * 3 * 16 * 4);

  // A smooth environment with every band up to 3 present and different per channel.
  const EquirectMap smooth = test::equirectOf(256, 128, [](const Vec& d) {
    return Vec{1.0 + 0.6 * d[1] + 0.3 * d[0] * d[2], 1.2 - 0.4 * d[2] + 0.2 * d[0] * d[1],
               0.9 + 0.5 * d[0] + 0.25 * d[1] * d[1] * d[2]};
  });
  const ShCoefficients environment = projectEnvironment(smooth, 3);

  // The largest relative difference between the table and the closed form over `views`,
  // asserting each is below `tolerance`.
  auto worstDifference = [&](const ShCoefficients& environment, const std::vector<Vec>& views,
                             double tolerance) {
    double worst = 0.0;
    for (const Vec& v : views) {
      const auto closed = shadeZonal(environment, zonal, v);
      const auto looked = table.shade(environment, v);
      for (size_t c = 0; c < 3; ++c) {
        const double e = std::abs(looked[c] - closed[c]) / closed[c];
        worst = std::max(worst, e);
        EXPECT_LT(e, tolerance) << "channel " << c << " at " << v[0] << "," << v[1] << "," << v[2];
      }
    }
    return worst;
  };
  // At the table's own texel centres the nearest texel is exact: only the float storage of the
  // transfer differs (~1e-7 relative, 16 terms), so 1e-5 relative.
  const double worstAtCentres = worstDifference(environment, cubeTexelCentres(128, 9), 1e-5);
  // Elsewhere the nearest texel centre is up to half a texel diagonal away, at most
  // sqrt(2) / 128 rad at a face centre: the l = 1..3 terms move by at most about l times that,
  // and they hold a fraction of the result, so 2e-2 relative bounds the quantisation. A wrong
  // face or texel would move the view by > 0.1 rad and break it.
  const double worstRandom = worstDifference(environment, randomDirections(3000, 31), 2e-2);
  // In a uniform environment the view does not matter: exact up to float storage.
  const ShCoefficients flat = projectEnvironment(uniformEquirect(256, 128, {0.5f, 1.0f, 2.0f}), 3);
  const double worstUniform = worstDifference(flat, randomDirections(3000, 41), 1e-5);
  std::cout << "paper table vs closed form: relative difference at texel centres " << worstAtCentres
            << ", random views " << worstRandom << ", uniform environment " << worstUniform << "\n";
}

// Minimum over channels and many directions of sum_lm L_lm Y_lm(d).
double minimumReconstruction(const ShCoefficients& coefficients, int order) {
  double lowest = 1e300;
  std::vector<double> basis;
  for (const Vec& d : lab::fibonacciDirections(20000)) {
    shBasis(order, d, basis);
    for (size_t c = 0; c < 3; ++c) {
      double sum = 0.0;
      for (size_t i = 0; i < basis.size(); ++i) sum += coefficients[i][c] * basis[i];
      lowest = std::min(lowest, sum);
    }
  }
  return lowest;
}

TEST(ShProjection, HannWindowTamesTheRingingAroundASun) {
  // The built-in environment holds a 1.5 degree sun 2000 times brighter than the sky: truncated
  // at order 8 its SH reconstruction rings negative far from it. Windowing trades sharpness for
  // a smaller negative lobe.
  constexpr int kOrder = 8;
  const EquirectMap environment = lab::builtinTestEnvironment();
  const double plain =
      minimumReconstruction(projectEnvironment(environment, kOrder, ShWindow::None), kOrder);
  const double hann =
      minimumReconstruction(projectEnvironment(environment, kOrder, ShWindow::Hann), kOrder);
  std::cout << "order-8 reconstruction minimum: no window " << plain << ", Hann " << hann << "\n";
  EXPECT_LT(plain, 0.0) << "the unwindowed sun should ring below zero";
  EXPECT_GT(hann, plain) << "the Hann window should make the most negative value smaller";
  EXPECT_LT(std::max(-hann, 0.0), -plain);
  // The window must leave band 0 alone (the mean radiance) and damp band 8 hardest.
  EXPECT_DOUBLE_EQ(shWindowFactor(ShWindow::Hann, 0, kOrder), 1.0);
  EXPECT_LT(shWindowFactor(ShWindow::Hann, kOrder, kOrder),
            shWindowFactor(ShWindow::Hann, 1, kOrder));
}

}  // namespace
}  // namespace pluvia::optics
