// RainRenderer against renderRainCpu (its exact CPU twin) on tiny targets, for both backends (the
// EGL pipeline and the CPU streak rasteriser): every pixel of the composite and of the rain
// planes must agree to 1e-3 relative (1e-5 absolute near zero).
//
// Edge rule: a pixel is left out of the comparison when its centre lies within 1e-3 px of an
// edge of some streak's quad. There the inside test (u, v in [0, 1]) can flip on one
// rounding difference between the two float evaluations, and a flip adds or drops a whole
// streak. The test asserts that this rule leaves out only a few pixels.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>

#include "gpu/rain_renderer.h"
#include "image/equirect.h"
#include "test_support.h"

namespace pluvia::gpu {
namespace {

constexpr int kWidth = 48, kHeight = 32;
constexpr double kEdgeBandPx = 1e-3;

// Three strokes with non-uniform profiles in a 24 x 20 atlas: a soft Gaussian streak, a
// streak that brightens toward its tail, and a ring with a transparent hole (matte 0, which
// exercises the alpha <= 0 discard).
rain::StrokeAtlas threeStrokeAtlas() {
  rain::StrokeAtlas atlas;
  atlas.width = 24;
  atlas.height = 20;
  atlas.alpha.assign(24 * 20, 0.0f);
  auto at = [&](int x, int y) -> float& { return atlas.alpha[y * 24 + x]; };
  for (int y = 0; y < 20; ++y) {
    for (int x = 0; x < 6; ++x) {
      const float across = (x + 0.5f - 3.0f) / 1.5f, along = (y + 0.5f - 10.0f) / 7.0f;
      at(x, y) = std::exp(-across * across - along * along);
    }
    for (int x = 6; x < 14; ++x) {
      at(x, y) = (y < 16) ? (0.1f + 0.05f * y) * (x % 2 ? 1.0f : 0.6f) : 0.0f;
    }
    for (int x = 14; x < 24; ++x) {
      const float r = std::hypot(x + 0.5f - 19.0f, y + 0.5f - 10.0f);
      at(x, y) = r < 2.0f ? 0.0f : std::max(0.0f, 1.0f - std::abs(r - 4.0f) / 3.0f);
    }
  }
  atlas.rects = {{0, 0, 6, 20}, {6, 0, 14, 16}, {14, 0, 24, 20}};
  return atlas;
}

// A dozen-plus streaks: many angles, widths 1..6 px, alphas (one above 1, one zero), still
// drops, streaks leaving the frame, overlaps whose order matters, and depths on both sides
// of the depth plane.
std::vector<rain::StreakInstance> mixedStreaks() {
  std::mt19937 random(2024);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<rain::StreakInstance> streaks;
  const float angles[] = {90, 80, 100, 45, 135, 0, 30, 170, 60, 115, 95, 10, 250, 300};
  for (int i = 0; i < 14; ++i) {
    const float radians = angles[i] * 3.14159265f / 180.0f;
    const float length = 4.0f + 22.0f * unit(random);
    const float headX = -3.0f + 54.0f * unit(random), headY = -2.0f + 36.0f * unit(random);
    float vx = unit(random) - 0.5f, vy = unit(random) - 0.5f, vz = unit(random) + 0.2f;
    const float n = std::sqrt(vx * vx + vy * vy + vz * vz);
    streaks.push_back({headX, headY, headX + length * std::cos(radians),
                       headY + length * std::sin(radians), 1.0f + 5.0f * (i % 6) / 5.0f,
                       0.25f + 0.06f * i, i % 3 == 0 ? 12.0f : 3.0f, static_cast<float>(i % 3),
                       vx / n, vy / n, vz / n, 0.0f});
  }
  streaks[3].alpha = 1.7f;              // matte * alpha clamps to 1
  streaks[7].alpha = 0.0f;              // drawn by neither
  streaks[5].tailX = streaks[5].headX;  // a still drop
  streaks[5].tailY = streaks[5].headY;
  streaks[11] = streaks[2];  // an exact overlap, drawn after: order matters
  streaks[11].strokeIndex = 2;
  streaks[11].widthPx = 2.5f;
  return streaks;
}

// Depth: 6 m on the left half, far (+inf) on the right, a NaN patch; streaks at 12 m are
// hidden on the left only.
void addDepthPlane(Image& frame) {
  std::vector<float>& depth = frame.plane("depth");
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) depth[y * kWidth + x] = x < kWidth / 2 ? 6.0f : INFINITY;
  }
  for (int y = 20; y < 24; ++y) depth[y * kWidth + 40] = NAN;
}

Image gradientBackground() {
  Image frame(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      float* p = frame.pixel(x, y);
      p[0] = 0.05f + 0.9f * x / kWidth;
      p[1] = 0.3f + 0.5f * std::sin(0.4f * y) * std::sin(0.4f * y);
      p[2] = 2.0f * (x + y) / (kWidth + kHeight);
      p[3] = 0.5f + 0.5f * y / kHeight;  // a varying alpha that must survive
    }
  }
  return frame;
}

Image uniformBackground(float value) {
  Image frame(kWidth, kHeight);
  for (size_t i = 0; i < frame.pixelCount(); ++i) {
    for (int c = 0; c < 3; ++c) frame.rgba[i * 4 + c] = value;
  }
  return frame;
}

rain::ShadingParams orderZeroShading() {
  rain::ShadingParams shading;
  shading.shOrder = 0;
  shading.envSh = {{1.2f, 0.9f, 0.7f}};
  shading.transferZonal = {0.8f};
  shading.backgroundWeight = 0.7f;
  return shading;
}

// An order-3 environment bright from +z and slightly coloured, with every coefficient
// non-zero, so each of the 16 basis functions contributes.
rain::ShadingParams orderThreeShading() {
  rain::ShadingParams shading;
  shading.shOrder = 3;
  std::mt19937 random(99);
  std::uniform_real_distribution<float> spread(-0.3f, 0.3f);
  for (int i = 0; i < 16; ++i) {
    shading.envSh.push_back({spread(random), spread(random), spread(random)});
  }
  shading.envSh[0] = {3.0f, 2.8f, 2.5f};
  shading.envSh[2] = {1.2f, 1.1f, 0.9f};
  shading.transferZonal = {1.0f, 0.75f, 0.4f, 0.2f};
  shading.backgroundWeight = 0.55f;
  return shading;
}

// Texels made bright in testRadianceMap().
std::vector<std::pair<int, int>> brightTexels(int width, int height) {
  return {{0, height * 5 / 16},
          {width - 1, height * 5 / 8},
          {width * 3 / 10, 0},
          {width * 7 / 10, height - 1},
          {width / 2, height / 2}};
}

// A drop radiance map: a smooth function of the texel's direction (0.4 .. 1.5 per channel)
// with a few bright texels (5 .. 7): on the u seam (first and last column), in the top and
// bottom rows and in the middle. Their contrast is kept below ~20: the float u of a lookup
// is quantised (1e-5 texel at width 128), and such a step times the contrast must stay well
// within the 1e-3 agreement.
EquirectMap testRadianceMap(int width, int height) {
  EquirectMap map = test::equirectOf(width, height, [](const std::array<double, 3>& d) {
    return std::array<double, 3>{0.9 + 0.4 * d[0] + 0.1 * d[1],
                                 0.8 + 0.3 * d[1] * d[2] + 0.2 * d[2],
                                 1.0 - 0.3 * d[1] + 0.2 * d[0] * d[0]};
  });
  for (const auto& [x, y] : brightTexels(width, height)) {
    float* t = map.texel(x, y);
    t[0] = 6.0f, t[1] = 5.0f, t[2] = 7.0f;
  }
  return map;
}

rain::ShadingParams mapOnlyShading(const EquirectMap& map) {
  rain::ShadingParams shading;
  shading.radianceMap = map;
  return shading;
}

std::array<float, 3> normalized(double x, double y, double z) {
  const double n = std::sqrt(x * x + y * y + z * z);
  return {static_cast<float>(x / n), static_cast<float>(y / n), static_cast<float>(z / n)};
}

// View directions that probe the lookup where it is delicate: near and at the poles (v
// clamps to the first and last rows), across the u seam (x ~ 0 on the +Z side, signed zeros
// included), around each bright texel (within a texel of its centre), then random ones.
std::vector<std::array<float, 3>> probeViews(int width, int height, int count) {
  std::vector<std::array<float, 3>> views = {{0.0f, 1.0f, 0.0f}, {0.0f, -1.0f, 0.0f}};
  const double ring = std::sqrt(1.0 - 0.999 * 0.999);
  for (double y : {0.999, -0.999}) {
    for (double phi : {0.1, 1.7, 3.1, 4.4}) {
      views.push_back(normalized(ring * std::cos(phi), y, ring * std::sin(phi)));
    }
  }
  for (double y : {0.0, 0.3, -0.6}) {
    for (double x : {0.0, -0.0, 1e-4, -1e-4, 3e-3, -3e-3, 0.02, -0.02}) {
      views.push_back(normalized(x, y, 1.0));
    }
  }
  for (const auto& [x, y] : brightTexels(width, height)) {
    for (auto [du, dv] : {std::pair{-0.3, -0.4}, {0.45, 0.2}, {-0.7, 0.6}, {0.1, -0.9}}) {
      const auto d = equirectDirection((x + 0.5 + du) / width, (y + 0.5 + dv) / height);
      views.push_back(normalized(d[0], d[1], d[2]));
    }
  }
  std::mt19937 random(31);
  std::normal_distribution<double> normal;
  while (static_cast<int>(views.size()) < count) {
    views.push_back(normalized(normal(random), normal(random), normal(random)));
  }
  views.resize(count);
  return views;
}

// Still drops (3 x 3 px squares, no pixel centre near an edge) on a 4 px grid, one per view.
// The rain planes hold alpha * C', so their comparison checks C' of every view.
std::vector<rain::StreakInstance> probeDrops(const EquirectMap& map) {
  constexpr int kColumns = kWidth / 4, kRows = kHeight / 4;
  const auto views = probeViews(map.width, map.height, kColumns * kRows);
  std::vector<rain::StreakInstance> drops;
  for (int k = 0; k < kColumns * kRows; ++k) {
    const float x = 4.0f * (k % kColumns) + 2.5f, y = 4.0f * (k / kColumns) + 2.5f;
    const auto& v = views[k];
    drops.push_back({x, y, x, y, 3.0f, 1.0f, 1.0f, 0.0f, v[0], v[1], v[2], 0.0f});
  }
  return drops;
}

// True when (x, y) lies within `band` px of an edge of the streak's quad (double precision,
// independent of the renderers' own geometry code).
bool nearQuadEdge(const rain::StreakInstance& s, double x, double y, double band) {
  double ax = s.tailX - s.headX, ay = s.tailY - s.headY;
  double length = std::hypot(ax, ay);
  if (length > 1e-4) {
    ax /= length, ay /= length;
  } else {
    ax = 0, ay = 1, length = 0;
  }
  const double rx = x - s.headX, ry = y - s.headY;
  const double along = rx * ax + ry * ay, across = -rx * ay + ry * ax;
  const double half = 0.5 * s.widthPx;
  const bool withinAlong = along >= -half - band && along <= length + half + band;
  const bool withinAcross = std::abs(across) <= half + band;
  const bool nearAcrossEdge = std::abs(std::abs(across) - half) <= band;
  const bool nearAlongEdge =
      std::abs(along + half) <= band || std::abs(along - length - half) <= band;
  return (nearAcrossEdge && withinAlong) || (nearAlongEdge && withinAcross);
}

struct Comparison {
  int compared = 0;
  int skippedNearEdges = 0;
  int mismatches = 0;
  int rainPixels = 0;  // pixels with rain.A > 0 on the CPU
  std::string firstMismatch;
};

bool close(float gpu, float cpu) {
  return std::abs(gpu - cpu) <= 1e-3f * std::abs(cpu) || std::abs(gpu - cpu) <= 1e-5f;
}

Comparison compare(const Image& gpu, const Image& cpu,
                   const std::vector<rain::StreakInstance>& streaks) {
  Comparison result;
  const char* planes[] = {"rain.R", "rain.G", "rain.B", "rain.A", "matte"};
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const bool nearEdge = std::any_of(streaks.begin(), streaks.end(), [&](const auto& s) {
        return s.widthPx > 0 && s.alpha > 0 && nearQuadEdge(s, x + 0.5, y + 0.5, kEdgeBandPx);
      });
      if (nearEdge) {
        ++result.skippedNearEdges;
        continue;
      }
      ++result.compared;
      const size_t i = static_cast<size_t>(y) * kWidth + x;
      if (cpu.findPlane("rain.A")->at(i) > 0.0f) ++result.rainPixels;
      std::string bad;
      for (int c = 0; c < 4; ++c) {
        if (!close(gpu.rgba[i * 4 + c], cpu.rgba[i * 4 + c])) {
          bad += " rgba[" + std::to_string(c) + "] " + std::to_string(gpu.rgba[i * 4 + c]) +
                 " vs " + std::to_string(cpu.rgba[i * 4 + c]);
        }
      }
      for (const char* name : planes) {
        const float g = gpu.findPlane(name)->at(i), c = cpu.findPlane(name)->at(i);
        if (!close(g, c))
          bad += std::string(" ") + name + " " + std::to_string(g) + " vs " + std::to_string(c);
      }
      if (!bad.empty()) {
        if (result.mismatches++ == 0) {
          result.firstMismatch = fmt::format("({},{}):{}", x, y, bad);
        }
      }
    }
  }
  return result;
}

class GpuVsCpu : public ::testing::TestWithParam<RainBackend> {
 protected:
  static void SetUpTestSuite() {
    for (int b = 0; b < 2; ++b) {
      renderers_[b] =
          new RainRenderer(kWidth, kHeight, b == 0 ? RainBackend::Egl : RainBackend::Cpu);
      renderers_[b]->setStrokeAtlas(threeStrokeAtlas());
    }
  }
  static void TearDownTestSuite() {
    for (RainRenderer*& renderer : renderers_) {
      delete renderer;
      renderer = nullptr;
    }
  }
  static RainRenderer& renderer() { return *renderers_[GetParam() == RainBackend::Egl ? 0 : 1]; }

  // Renders `background` both ways and checks they agree; returns the comparison.
  static Comparison renderBoth(const Image& background,
                               const std::vector<rain::StreakInstance>& streaks,
                               const rain::ShadingParams& shading,
                               int maxSkippedNearEdges = kWidth * kHeight / 100) {
    Image gpu = background, cpu = background;
    renderer().render(gpu, streaks, shading);
    renderRainCpu(cpu, streaks, shading, threeStrokeAtlas());
    const Comparison result = compare(gpu, cpu, streaks);
    EXPECT_EQ(result.mismatches, 0) << "first mismatch at " << result.firstMismatch;
    EXPECT_LT(result.skippedNearEdges, maxSkippedNearEdges) << "the edge rule hides too much";
    return result;
  }

  static RainRenderer* renderers_[2];
};
RainRenderer* GpuVsCpu::renderers_[2] = {nullptr, nullptr};

TEST_P(GpuVsCpu, OrderZeroWithDepthPlane) {
  Image background = gradientBackground();
  addDepthPlane(background);
  const Comparison result = renderBoth(background, mixedStreaks(), orderZeroShading());
  EXPECT_GT(result.rainPixels, 200) << "the scene must put rain on many pixels";
}

TEST_P(GpuVsCpu, OrderThreeWithDepthPlane) {
  Image background = gradientBackground();
  addDepthPlane(background);
  const Comparison result = renderBoth(background, mixedStreaks(), orderThreeShading());
  EXPECT_GT(result.rainPixels, 200);
}

TEST_P(GpuVsCpu, OrderThreeWithoutDepthPlane) {
  renderBoth(gradientBackground(), mixedStreaks(), orderThreeShading());
}

TEST_P(GpuVsCpu, VeryBrightBackground) {
  renderBoth(uniformBackground(1.0e4f), mixedStreaks(), orderThreeShading());
}

TEST_P(GpuVsCpu, BlackBackground) {
  renderBoth(uniformBackground(0.0f), mixedStreaks(), orderZeroShading());
}

TEST_P(GpuVsCpu, ManyThinStreaksAtSubPixelOffsets) {
  // Width 1 streaks at fractional positions: the pixel-centre coverage test at its finest.
  std::vector<rain::StreakInstance> streaks;
  for (int i = 0; i < 60; ++i) {
    const float x = 0.37f + 0.79f * i, y = 0.21f + 0.43f * (i % 17);
    streaks.push_back({x, y, x + 3.3f + 0.1f * i, y + 12.7f - 0.2f * i, 1.0f + 0.05f * (i % 7),
                       0.9f, 1.0f, static_cast<float>(i % 3), 0.0f, 0.6f, 0.8f, 0.0f});
  }
  renderBoth(gradientBackground(), streaks, orderThreeShading());
}

TEST_P(GpuVsCpu, EveryLineWidthClassTrianglesAndTheFrameEdges) {
  // Widths from sub-pixel to wider than the widest line (drawn as triangles), at angles on
  // both sides of 45 degrees (where GL switches the line's major axis), with heads on and
  // beyond all four edges of the frame: a wide line whose centre leaves the viewport must
  // still cover the pixels its width reaches inside (the guard band).
  std::vector<rain::StreakInstance> streaks;
  const float widths[] = {0.6f, 1.0f, 1.9f, 2.2f, 3.1f, 4.5f, 7.0f, 11.0f, 20.0f, 70.0f};
  const float angles[] = {90.0f, 44.0f, 46.0f, 135.0f, 3.0f, 178.0f, 270.0f, 61.0f};
  const float heads[][2] = {{-2.5f, 10.3f}, {50.2f, 20.7f}, {20.4f, -3.1f}, {30.6f, 33.8f},
                            {12.3f, 14.9f}, {47.4f, 0.6f},  {0.4f, 31.2f},  {35.5f, 16.1f}};
  int k = 0;
  for (float width : widths) {
    for (int j = 0; j < 2; ++j, ++k) {
      const float radians = angles[k % 8] * 3.14159265f / 180.0f;
      const float x = heads[(k * 3) % 8][0], y = heads[(k * 3) % 8][1];
      const float length = 3.0f + 2.5f * (k % 7);
      streaks.push_back({x, y, x + length * std::cos(radians), y + length * std::sin(radians),
                         width, width > 10.0f ? 0.08f : 0.3f, 1.0f, static_cast<float>(k % 3), 0.0f,
                         0.6f, 0.8f, 0.0f});
    }
  }
  // The widest streaks run edges across the whole frame: allow 3 % of pixels near an edge.
  const Comparison result =
      renderBoth(gradientBackground(), streaks, orderThreeShading(), kWidth * kHeight * 3 / 100);
  EXPECT_GT(result.rainPixels, kWidth * kHeight / 2);
}

TEST_P(GpuVsCpu, SceneDepthHidesTheFarStreaksOnTheLeft) {
  // The comparison above could pass with a depth test that both sides get wrong: check the
  // intended outcome directly. A 12 m streak on the left (depth 6 m) is hidden, on the right
  // (far) it shows.
  Image frame = gradientBackground();
  addDepthPlane(frame);
  const std::vector<rain::StreakInstance> streaks = {
      {10.0f, 4.0f, 10.0f, 28.0f, 4.0f, 1.0f, 12.0f, 1.0f, 0, 0, 1, 0},
      {36.0f, 4.0f, 36.0f, 28.0f, 4.0f, 1.0f, 12.0f, 1.0f, 0, 0, 1, 0}};
  Image cpu = frame;
  renderer().render(frame, streaks, orderZeroShading());
  renderRainCpu(cpu, streaks, orderZeroShading(), threeStrokeAtlas());
  const auto& matte = frame.plane("matte");
  float left = 0, right = 0;
  for (int y = 4; y < 28; ++y) {
    left += matte[y * kWidth + 10];
    right += matte[y * kWidth + 36];
  }
  EXPECT_EQ(left, 0.0f);
  EXPECT_GT(right, 1.0f);
  EXPECT_EQ(compare(frame, cpu, streaks).mismatches, 0);
}

TEST_P(GpuVsCpu, RadianceMapAloneAtDelicateViews) {
  for (auto [width, height] : {std::pair{16, 8}, {128, 64}}) {
    SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height) + " map");
    const EquirectMap map = testRadianceMap(width, height);
    const Comparison result =
        renderBoth(gradientBackground(), probeDrops(map), mapOnlyShading(map));
    EXPECT_GT(result.rainPixels, 8 * 96) << "every drop must show";
  }
}

TEST_P(GpuVsCpu, RadianceMapAloneOnOverlappingStreaks) {
  Image background = gradientBackground();
  addDepthPlane(background);
  const Comparison result =
      renderBoth(background, mixedStreaks(), mapOnlyShading(testRadianceMap(128, 64)));
  EXPECT_GT(result.rainPixels, 200);
}

TEST_P(GpuVsCpu, RadianceMapWithShAndBackground) {
  for (auto [width, height] : {std::pair{16, 8}, {128, 64}}) {
    SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height) + " map");
    rain::ShadingParams shading = orderThreeShading();  // c = 0.55
    shading.radianceMap = testRadianceMap(width, height);
    Image background = gradientBackground();
    addDepthPlane(background);
    renderBoth(background, mixedStreaks(), shading);
    renderBoth(gradientBackground(), probeDrops(shading.radianceMap), shading);
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, GpuVsCpu, ::testing::Values(RainBackend::Egl, RainBackend::Cpu),
                         [](const auto& info) {
                           return std::string(info.param == RainBackend::Egl ? "Egl" : "Cpu");
                         });

// Streaks lit by local lights: the term C + bead(v) * local, beaded along the streak, agrees
// between the backends and the exact twin, and adds light where it is set.
TEST(GpuVsCpuLocalLights, BeadedLocalLightTermAgrees) {
  std::vector<rain::StreakInstance> streaks = mixedStreaks();
  for (size_t i = 0; i < streaks.size(); i += 2) {
    streaks[i].localR = 2.0f;
    streaks[i].localG = 1.5f;
    streaks[i].localB = 0.5f;
    streaks[i].beadCycles = 3.7f;
    streaks[i].beadPhase = 0.3f;
    streaks[i].glintMode20 = 0.8f;
    streaks[i].glintMode31 = -1.2f;
  }
  Image background = gradientBackground();
  addDepthPlane(background);
  for (RainBackend backend : {RainBackend::Egl, RainBackend::Cpu}) {
    RainRenderer renderer(kWidth, kHeight, backend);
    renderer.setStrokeAtlas(threeStrokeAtlas());
    Image lit = background, exact = background, unlit = background;
    renderer.render(lit, streaks, orderZeroShading());
    renderRainCpu(exact, streaks, orderZeroShading(), threeStrokeAtlas());
    renderer.render(unlit, mixedStreaks(), orderZeroShading());
    const Comparison result = compare(lit, exact, streaks);
    EXPECT_EQ(result.mismatches, 0) << "first mismatch at " << result.firstMismatch;
    double litSum = 0, unlitSum = 0;
    for (size_t p = 0; p < lit.pixelCount(); ++p) {
      litSum += lit.plane("rain.R")[p];
      unlitSum += unlit.plane("rain.R")[p];
    }
    EXPECT_GT(litSum, 1.2 * unlitSum);
  }
}

}  // namespace
}  // namespace pluvia::gpu
