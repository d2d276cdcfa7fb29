// Level of detail for far rain (rain.lod_px, gpu/far_drop_lines.h): the single-pixel lines that
// stand in for the far drops' streaks, against drawing every drop as its own textured streak.
//
// Tolerances: a line keeps its streak's coverage mass, so the frame's mean rain alpha and mean
// rain radiance with lines are within 3 % of drawing every streak (the sampled simulation below
// gives about 1 %: overlapping streaks blend "over", and a quad's bilinear matte at pixel
// centres is not exactly its mean). One faint streak on its own is kept to 1 % of its analytic
// mass alpha * meanMatte * width * (length + width). With
// lod_px 0 nothing changes: the streaks and the frame are bit-identical to the call without a
// far list.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <numeric>

#include "geometry/camera.h"
#include "gpu/rain_renderer.h"
#include "lab/test_environment.h"
#include "rain/drop_simulation.h"
#include "rain/stroke_library.h"

namespace pluvia::gpu {
namespace {

constexpr int kWidth = 320, kHeight = 240;
// At 320 px wide (a 277 px focal length) a 1 mm drop spans 0.25 px at 1.1 m: the far drops are
// most of the population, the near ones still hundreds.
constexpr double kLodPx = 0.25;

std::unique_ptr<rain::DropSimulation> makeSimulation() {
  rain::DropSimulationSettings settings;
  settings.maxDrops = 30000;
  settings.seed = 11u;
  settings.nearMeters = 0.5;
  const Camera camera = Camera::fromFieldOfView(kWidth, kHeight, 60.0, 0.0, 1.6);
  rain::RainAtFrame rain;
  rain.rateMmPerHour = 40.0;
  rain.densityScale = 4.0;
  rain.windSpeedMetersPerSecond = 2.5;
  auto simulation = std::make_unique<rain::DropSimulation>(
      settings, [camera](double) { return camera; }, [rain](double) { return rain; });
  simulation->advanceTo(2);
  return simulation;
}

rain::StreakSettings lookOf(const rain::StrokeAtlas& atlas, double lodPx) {
  rain::StreakSettings look;
  look.exposureSeconds = 1.0 / 48.0;
  look.opacity = 4.0;
  look.strokeCount = static_cast<int>(atlas.rects.size());
  look.meanMatte = rain::meanMatte(atlas);
  look.lodPx = lodPx;
  return look;
}

rain::ShadingParams mapShading() {
  rain::ShadingParams shading;
  shading.radianceMap = lab::builtinTestEnvironment(64);
  return shading;
}

double planeMean(const Image& frame, const char* name) {
  const std::vector<float>& plane = *frame.findPlane(name);
  return std::accumulate(plane.begin(), plane.end(), 0.0) / static_cast<double>(plane.size());
}

class FarDropLinesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    atlas_ = rain::loadStrokeLibrary(rain::builtinStrokeLibraryPath()).atlas;
  }
  Image render(const std::vector<rain::StreakInstance>& near,
               const std::vector<rain::StreakInstance>& far, const Image& background,
               RainBackend backend = RainBackend::Cpu) {
    RainRenderer renderer(kWidth, kHeight, backend);
    renderer.setStrokeAtlas(atlas_);
    Image frame = background;
    renderer.render(frame, near, mapShading(), far);
    return frame;
  }
  rain::StrokeAtlas atlas_;
};

Image greyFrame() {
  Image frame(kWidth, kHeight);
  for (size_t i = 0; i < frame.pixelCount(); ++i) {
    for (int c = 0; c < 3; ++c) frame.rgba[i * 4 + c] = 0.4f;
  }
  return frame;
}

TEST_F(FarDropLinesTest, LinesKeepTheMeanCoverageAndRadianceOfDrawingEveryDrop) {
  const auto simulation = makeSimulation();
  std::vector<rain::StreakInstance> far;
  const std::vector<rain::StreakInstance> near =
      simulation->buildStreaks(lookOf(atlas_, kLodPx), &far);
  ASSERT_GT(far.size(), 1000u) << "the population must have far drops for the test to mean much";
  ASSERT_GT(near.size(), 10u);
  std::vector<rain::StreakInstance> every = far;
  every.insert(every.end(), near.begin(), near.end());

  const Image background = greyFrame();
  const Image full = render(every, {}, background);
  const Image lined = render(near, far, background);
  const Image nearOnly = render(near, {}, background);
  const double fullAlpha = planeMean(full, "rain.A"), linedAlpha = planeMean(lined, "rain.A");
  // The far drops must matter: without them the coverage is clearly lower.
  EXPECT_LT(planeMean(nearOnly, "rain.A"), 0.8 * fullAlpha);
  EXPECT_NEAR(linedAlpha / fullAlpha, 1.0, 0.03);
  for (const char* channel : {"rain.R", "rain.G", "rain.B"}) {
    EXPECT_NEAR(planeMean(lined, channel) / planeMean(full, channel), 1.0, 0.03) << channel;
  }
}

TEST_F(FarDropLinesTest, OneFaintStreakKeepsItsAnalyticMass) {
  // alpha * meanMatte(stroke) * width * (length + width): the matte integrated over its quad.
  rain::StreakInstance streak{};
  streak.headX = 150.3f, streak.headY = 100.7f, streak.tailX = 153.1f, streak.tailY = 124.2f;
  streak.widthPx = 1.5f, streak.alpha = 0.02f, streak.depthMeters = 9.0f;
  streak.strokeIndex = 3.0f;
  streak.viewZ = -1.0f;
  const float length = std::hypot(streak.tailX - streak.headX, streak.tailY - streak.headY);
  // The mean over stroke 3's rectangle, computed here independently of the layer.
  const auto& rect = atlas_.rects[3];
  double matteSum = 0.0;
  int texels = 0;
  for (int y = int(rect[1]); y < int(rect[3]); ++y) {
    for (int x = int(rect[0]); x < int(rect[2]); ++x, ++texels) {
      matteSum += atlas_.alpha[size_t(y) * atlas_.width + x];
    }
  }
  const double mass = 0.02 * (matteSum / texels) * 1.5 * (length + 1.5);
  const Image lined = render({}, {streak}, greyFrame());
  const double sum = planeMean(lined, "rain.A") * kWidth * kHeight;
  EXPECT_NEAR(sum / mass, 1.0, 0.01);
  // Drawn as a quad the same streak covers the same mass (within the matte's bilinear
  // sampling at its pixel centres).
  const Image drawn = render({streak}, {}, greyFrame());
  EXPECT_NEAR(planeMean(drawn, "rain.A") * kWidth * kHeight / mass, 1.0, 0.1);
}

TEST_F(FarDropLinesTest, LinesAreHiddenBehindANearerScene) {
  const auto simulation = makeSimulation();
  std::vector<rain::StreakInstance> far;
  const std::vector<rain::StreakInstance> near =
      simulation->buildStreaks(lookOf(atlas_, kLodPx), &far);
  float nearestFar = INFINITY;
  for (const auto& s : far) nearestFar = std::min(nearestFar, s.depthMeters);
  ASSERT_GT(nearestFar, 0.5f);
  // A wall at 0.5 m over the left half (in front of every far drop), sky elsewhere.
  Image background = greyFrame();
  std::vector<float>& depth = background.plane("depth");
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x)
      depth[size_t(y) * kWidth + x] = x < kWidth / 2 ? 0.5f : INFINITY;
  const Image lined = render({}, far, background);
  const std::vector<float>& alpha = *lined.findPlane("rain.A");
  double left = 0.0, right = 0.0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x)
      (x < kWidth / 2 ? left : right) += alpha[size_t(y) * kWidth + x];
  }
  EXPECT_EQ(left, 0.0);
  EXPECT_GT(right, 0.0);
}

TEST_F(FarDropLinesTest, LodOffReproducesTheFrame) {
  const auto simulation = makeSimulation();
  std::vector<rain::StreakInstance> far{rain::StreakInstance{}};
  const std::vector<rain::StreakInstance> withList =
      simulation->buildStreaks(lookOf(atlas_, 0.0), &far);
  const std::vector<rain::StreakInstance> every = simulation->buildStreaks(lookOf(atlas_, 0.0));
  EXPECT_TRUE(far.empty());
  ASSERT_EQ(withList.size(), every.size());
  EXPECT_EQ(std::memcmp(withList.data(), every.data(), every.size() * sizeof(every[0])), 0);

  RainRenderer renderer(kWidth, kHeight, RainBackend::Cpu);
  renderer.setStrokeAtlas(atlas_);
  Image a = greyFrame(), b = greyFrame();
  renderer.render(a, every, mapShading());
  renderer.render(b, every, mapShading(), {});
  EXPECT_EQ(a.rgba, b.rgba);
  EXPECT_EQ(*a.findPlane("rain.A"), *b.findPlane("rain.A"));
}

TEST_F(FarDropLinesTest, EglAndCpuComposeTheSameLines) {
  const auto simulation = makeSimulation();
  std::vector<rain::StreakInstance> far;
  const std::vector<rain::StreakInstance> near =
      simulation->buildStreaks(lookOf(atlas_, kLodPx), &far);
  Image egl;
  try {
    egl = render(near, far, greyFrame(), RainBackend::Egl);
  } catch (const std::exception& error) {
    GTEST_SKIP() << "no EGL: " << error.what();
  }
  const Image cpu = render(near, far, greyFrame(), RainBackend::Cpu);
  EXPECT_NEAR(planeMean(egl, "rain.A") / planeMean(cpu, "rain.A"), 1.0, 1e-3);
  EXPECT_NEAR(planeMean(egl, "rain.G") / planeMean(cpu, "rain.G"), 1.0, 1e-3);
}

}  // namespace
}  // namespace pluvia::gpu
