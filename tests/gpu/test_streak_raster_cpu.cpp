// The CPU streak rasteriser (RainRenderer's Cpu backend) against the EGL backend on a real frame
// size with the built-in stroke atlas (strokes cut from real rain footage), simulated heavy
// rain, a scene depth and the background term; its AVX2 and portable paths against each
// other; its independence from the thread count; and how a renderer chooses its backend.
//
// Tolerance, EGL against CPU: a pixel agrees when every channel of the composite and of the
// rain planes is within 1e-3 relative or 1e-5 absolute (as test_rain_gpu_vs_cpu.cpp). Pixels
// whose centre lies within rounding (about 1e-5 px) of a streak's edge may flip a whole streak
// in or out between the two float evaluations; that must stay below 0.1 % of the pixels, and
// the mean rain alpha of the two must agree to 1e-4 relative.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <string>

#include "geometry/camera.h"
#include "gpu/rain_renderer.h"
#include "gpu/streak_batches.h"
#include "gpu/streak_raster_cpu.h"
#include "lab/test_environment.h"
#include "rain/drop_simulation.h"
#include "rain/stroke_library.h"
#include "util/error.h"

namespace pluvia::gpu {
namespace {

constexpr int kWidth = 320, kHeight = 240;

// Heavy rain (40 mm/h) for a 60-degree camera 1.6 m above the ground, 1/60 s, a breeze:
// streaks from the drop simulation, near ones wide and defocused, far ones sub-pixel.
std::vector<rain::StreakInstance> simulatedRain(const rain::StrokeAtlas& atlas) {
  rain::DropSimulationSettings settings;
  settings.maxDrops = 30000;
  settings.seed = 7u;
  const Camera camera = Camera::fromFieldOfView(kWidth, kHeight, 60.0, 0.0, 1.6);
  rain::RainAtFrame rain;
  rain.rateMmPerHour = 40.0;
  rain.densityScale = 4.0;
  rain.windSpeedMetersPerSecond = 3.0;
  rain::DropSimulation simulation(
      settings, [camera](double) { return camera; }, [rain](double) { return rain; });
  simulation.advanceTo(2);
  rain::StreakSettings look;
  look.exposureSeconds = 1.0 / 60.0;
  look.opacity = 10.0;  // the bundled example's showcase look is 8
  look.strokeCount = static_cast<int>(atlas.rects.size());
  look.meanMatte = rain::meanMatte(atlas);
  look.focusMeters = 20.0, look.fNumber = 11.0;
  return simulation.buildStreaks(look);
}

// A street plate's depth: sky above the horizon, the ground below it (z = h f / (y - cy)), a
// wall 5 m away over the left third; and a plate that is brighter at the top.
Image streetFrame() {
  Image frame(kWidth, kHeight);
  std::vector<float>& depth = frame.plane("depth");
  const float focalPx = 0.5f * kWidth / std::tan(30.0f * 3.14159265f / 180.0f);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const float below = y + 0.5f - 0.5f * kHeight;
      float z = below > 0.0f ? 1.6f * focalPx / below : INFINITY;
      if (x < kWidth / 3) z = std::min(z, 5.0f);
      depth[static_cast<size_t>(y) * kWidth + x] = z;
      float* p = frame.pixel(x, y);
      p[0] = 0.9f - 0.6f * y / kHeight, p[1] = 0.8f - 0.5f * y / kHeight, p[2] = 0.7f;
    }
  }
  return frame;
}

rain::ShadingParams plateShading() {
  rain::ShadingParams shading;
  shading.radianceMap = lab::builtinTestEnvironment(128);
  shading.backgroundWeight = 0.3f;
  return shading;
}

bool close(float a, float b) {
  return std::abs(a - b) <= 1e-3f * std::abs(b) || std::abs(a - b) <= 1e-5f;
}

// Pixels where any channel of the composite or the rain planes disagrees.
int disagreeingPixels(const Image& a, const Image& b) {
  int count = 0;
  for (size_t i = 0; i < a.pixelCount(); ++i) {
    bool same = true;
    for (int c = 0; c < 4; ++c) same = same && close(a.rgba[i * 4 + c], b.rgba[i * 4 + c]);
    for (const char* name : {"rain.R", "rain.G", "rain.B", "rain.A", "matte"}) {
      same = same && close(a.findPlane(name)->at(i), b.findPlane(name)->at(i));
    }
    count += same ? 0 : 1;
  }
  return count;
}

double meanPlane(const Image& image, const char* name) {
  double sum = 0.0;
  for (float v : *image.findPlane(name)) sum += v;
  return sum / static_cast<double>(image.pixelCount());
}

class StreakRasterCpuTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    atlas_ = new rain::StrokeAtlas(rain::loadStrokeLibrary(rain::builtinStrokeLibraryPath()).atlas);
    streaks_ = new std::vector<rain::StreakInstance>(simulatedRain(*atlas_));
  }
  static void TearDownTestSuite() {
    delete atlas_;
    delete streaks_;
  }
  static rain::StrokeAtlas* atlas_;
  static std::vector<rain::StreakInstance>* streaks_;
};
rain::StrokeAtlas* StreakRasterCpuTest::atlas_ = nullptr;
std::vector<rain::StreakInstance>* StreakRasterCpuTest::streaks_ = nullptr;

TEST_F(StreakRasterCpuTest, MatchesTheEglBackendOnSimulatedRain) {
  ASSERT_GT(streaks_->size(), 3000u) << "the scene must hold thousands of streaks";
  RainRenderer egl(kWidth, kHeight, RainBackend::Egl), cpu(kWidth, kHeight, RainBackend::Cpu);
  egl.setStrokeAtlas(*atlas_);
  cpu.setStrokeAtlas(*atlas_);
  Image byEgl = streetFrame(), byCpu = streetFrame();
  egl.render(byEgl, *streaks_, plateShading());
  cpu.render(byCpu, *streaks_, plateShading());
  const int disagreeing = disagreeingPixels(byEgl, byCpu);
  const double alphaEgl = meanPlane(byEgl, "rain.A"), alphaCpu = meanPlane(byCpu, "rain.A");
  std::cout << "streaks " << streaks_->size() << ", pixels disagreeing " << disagreeing << " of "
            << kWidth * kHeight << ", mean rain alpha EGL " << alphaEgl << " CPU " << alphaCpu
            << "\n";
  EXPECT_GT(alphaCpu, 1e-3) << "the rain must cover the frame visibly";
  EXPECT_LE(disagreeing, kWidth * kHeight / 1000);
  EXPECT_NEAR(alphaCpu, alphaEgl, 1e-4 * alphaEgl);
}

TEST_F(StreakRasterCpuTest, Avx2AndPortablePathsAgree) {
  if (!detail::cpuHasAvx2()) GTEST_SKIP() << "this CPU has no AVX2 + FMA: only one path runs";
  StreakRasterCpu fast, portable(/*portableOnly=*/true);
  fast.setStrokeAtlas(*atlas_);
  portable.setStrokeAtlas(*atlas_);
  const std::vector<rain::StreakInstance> ordered = orderForDrawing(*streaks_).streaks;
  Image a = streetFrame(), b = streetFrame();
  fast.render(a, ordered, plateShading());
  portable.render(b, ordered, plateShading());
  // Both make the same float operations up to FMA contraction: every pixel within 1e-5.
  int differing = 0;
  for (size_t i = 0; i < a.pixelCount() * 4; ++i) {
    differing += std::abs(a.rgba[i] - b.rgba[i]) <= 1e-5f * std::max(1.0f, std::abs(b.rgba[i]));
  }
  EXPECT_EQ(differing, static_cast<int>(a.pixelCount() * 4)) << "values within 1e-5";
  EXPECT_LE(disagreeingPixels(a, b), kWidth * kHeight / 1000);
}

TEST_F(StreakRasterCpuTest, PictureDoesNotDependOnTheThreadCount) {
  RainRenderer cpu(kWidth, kHeight, RainBackend::Cpu);
  cpu.setStrokeAtlas(*atlas_);
  Image all = streetFrame(), one = streetFrame();
  cpu.render(all, *streaks_, plateShading());
  tbb::task_arena single(1);
  single.execute([&] { cpu.render(one, *streaks_, plateShading()); });
  EXPECT_EQ(all.rgba, one.rgba);
  EXPECT_EQ(*all.findPlane("rain.A"), *one.findPlane("rain.A"));
}

TEST(RainBackendChoice, SoftwareRenderersAreRecognised) {
  EXPECT_TRUE(isSoftwareGlRenderer("llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile)"));
  EXPECT_TRUE(isSoftwareGlRenderer("softpipe"));
  EXPECT_TRUE(isSoftwareGlRenderer("Google SwiftShader"));
  EXPECT_FALSE(isSoftwareGlRenderer("NVIDIA H100 80GB HBM3/PCIe/SSE2, OpenGL 4.6.0 NVIDIA 535"));
  EXPECT_FALSE(isSoftwareGlRenderer("AMD Radeon Pro W7900 (radeonsi, navi31, LLVM 15.0.7)"));
}

// Sets the default backend (what $PLUVIA_RAIN_BACKEND sets) for the scope, Auto after.
class DefaultBackend {
 public:
  explicit DefaultBackend(RainBackend backend) { setRainBackend(backend); }
  ~DefaultBackend() { setRainBackend(RainBackend::Auto); }
};

TEST(RainBackendChoice, AutoDrawsOnTheCpuExactlyWhenTheEglDeviceIsSoftware) {
  DefaultBackend unset(RainBackend::Auto);
  const std::string device = RainRenderer(8, 8, RainBackend::Egl).deviceDescription();
  RainRenderer automatic(8, 8);
  EXPECT_EQ(automatic.backend(), isSoftwareGlRenderer(device) ? RainBackend::Cpu : RainBackend::Egl)
      << device;
  if (automatic.backend() == RainBackend::Cpu) {
    EXPECT_NE(automatic.deviceDescription().find("software"), std::string::npos)
        << automatic.deviceDescription();
  }
}

TEST(RainBackendChoice, TheDefaultBackendOverridesAuto) {
  {
    DefaultBackend egl(*rainBackendNamed("egl"));
    EXPECT_EQ(RainRenderer(8, 8).backend(), RainBackend::Egl);
    // An explicit choice in code is not overridden.
    EXPECT_EQ(RainRenderer(8, 8, RainBackend::Cpu).backend(), RainBackend::Cpu);
  }
  {
    DefaultBackend cpu(*rainBackendNamed("CPU"));
    EXPECT_EQ(RainRenderer(8, 8).backend(), RainBackend::Cpu);
  }
  EXPECT_EQ(rainBackendNamed("Auto"), RainBackend::Auto);
  EXPECT_FALSE(rainBackendNamed("vulkan"));
}

}  // namespace
}  // namespace pluvia::gpu
