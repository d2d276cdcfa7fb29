// The depth stage's COLMAP source in a render: clips of the synthetic street
// (gpu/synthetic_scene.h) written as PNG sequences, tracked by the real colmap. A walk tracks,
// renders with the tracked camera, caches its tracking (plan: needed, then cached) and reuses it; a
// colmap that cannot run (naming its log) and a tripod pan (no parallax, found before COLMAP runs)
// stop the render before any frame, unless depth.fallback = layers, which renders with the manual
// layers and says why.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "gpu/synthetic_scene.h"
#include "sfm/colmap_runner.h"
#include "test_support.h"

namespace pluvia {
namespace {

namespace stdfs = std::filesystem;

constexpr int kWidth = 320;
constexpr int kHeight = 180;
constexpr int kFrames = 12;

size_t countFiles(const stdfs::path& dir, const std::string& extension) {
  size_t n = 0;
  for (const auto& entry : stdfs::directory_iterator(dir))
    n += entry.path().extension() == extension ? 1 : 0;
  return n;
}

// Writes frames 1..kFrames of `keys` as dir/street.####.png; returns the sequence pattern.
std::string writeClip(const stdfs::path& dir, const std::vector<gpu::SyntheticPathKey>& keys) {
  gpu::SyntheticSceneRenderer renderer(kWidth, kHeight);
  const gpu::SyntheticView intrinsics = gpu::defaultSyntheticIntrinsics(kWidth, kHeight);
  for (int i = 0; i < kFrames; ++i) {
    Image frame = renderer.render(gpu::syntheticViewAt(intrinsics, keys[size_t(i)]));
    test::writeImageFile(dir / fmt::format("street.{:04d}.png", i + 1), frame);
  }
  return (dir / "street.####.png").string();
}

// A walk: every 4th key of the default 48-frame path (0.2 m a frame down the street).
std::vector<gpu::SyntheticPathKey> walk() {
  const auto path = gpu::defaultSyntheticPath(48);
  std::vector<gpu::SyntheticPathKey> keys;
  for (int i = 0; i < kFrames; ++i) keys.push_back(path[size_t(4 * i)]);
  return keys;
}

// A tripod pan: the first key's position, yaw from -6 to +5 degrees.
std::vector<gpu::SyntheticPathKey> pan() {
  std::vector<gpu::SyntheticPathKey> keys(kFrames, gpu::defaultSyntheticPath(1)[0]);
  for (int i = 0; i < kFrames; ++i) keys[size_t(i)].yawDeg = -6.0 + i;
  return keys;
}

std::vector<std::string> renderArgs(const std::string& clip, const stdfs::path& out,
                                    const std::vector<std::string>& sets) {
  std::vector<std::string> args{"render", clip,   "-o",    (out / "wet.####.png").string(),
                                "-p",     "base", "--set", "depth.source=colmap"};
  for (const std::string& set : sets) args.insert(args.end(), {"--set", set});
  return args;
}

class CliDepthColmap : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!colmapAvailable()) GTEST_SKIP() << "colmap is not installed";
  }
};

TEST_F(CliDepthColmap, TrackedWalkRendersCachesAndReusesItsTracking) {
  const stdfs::path dir = test::freshTempDir("depth_colmap_walk");
  const std::string clip = writeClip(dir, walk());
  const stdfs::path cache = dir / "cache", out = dir / "out";
  stdfs::create_directories(out);
  const std::vector<std::string> sets{"camera.fov_deg=60", "camera.height_m=1.6"};
  std::vector<std::string> plan{"plan",    clip,           "-p",    "base",
                                "--cache", cache.string(), "--set", "depth.source=colmap"};
  for (const std::string& set : sets) plan.insert(plan.end(), {"--set", set});

  auto before = test::runPluvia(plan);
  ASSERT_EQ(before.exitCode, 0) << before.output;
  EXPECT_NE(before.output.find("per-clip analysis needed (not in the cache)"), std::string::npos)
      << before.output;

  std::vector<std::string> render = renderArgs(clip, out, sets);
  render.insert(render.end(), {"--cache", cache.string()});
  auto first = test::runPluvia(render);
  ASSERT_EQ(first.exitCode, 0) << first.output;
  EXPECT_NE(first.output.find(fmt::format("COLMAP registered {} of {} frames", kFrames, kFrames)),
            std::string::npos)
      << first.output;
  EXPECT_NE(first.output.find("rain: camera tracked by COLMAP"), std::string::npos) << first.output;
  EXPECT_EQ(countFiles(out, ".png"), size_t(kFrames));
  // The workspace (frames, database) is removed once the tracking is in the cache.
  for (const auto& entry : stdfs::directory_iterator(cache))
    EXPECT_FALSE(entry.is_directory()) << entry.path();

  auto after = test::runPluvia(plan);
  ASSERT_EQ(after.exitCode, 0) << after.output;
  EXPECT_NE(after.output.find("per-clip analysis cached"), std::string::npos) << after.output;

  stdfs::remove_all(out);
  stdfs::create_directories(out);
  auto second = test::runPluvia(render);
  ASSERT_EQ(second.exitCode, 0) << second.output;
  EXPECT_NE(second.output.find("COLMAP tracking from cache"), std::string::npos) << second.output;
  EXPECT_EQ(second.output.find("COLMAP registered"), std::string::npos) << second.output;
  EXPECT_EQ(countFiles(out, ".png"), size_t(kFrames));
}

TEST_F(CliDepthColmap, MissingColmapStopsBeforeAnyFrameUnlessFallbackAllowsLayers) {
  const stdfs::path dir = test::freshTempDir("depth_colmap_missing_render");
  const std::string clip = writeClip(dir, walk());
  const stdfs::path out = dir / "out";
  stdfs::create_directories(out);
  ::setenv("PLUVIA_COLMAP", "/nonexistent/colmap", 1);
  auto refused = test::runPluvia(renderArgs(clip, out, {}));
  auto fallback = test::runPluvia(renderArgs(clip, out, {"depth.fallback=layers"}));
  ::unsetenv("PLUVIA_COLMAP");

  EXPECT_EQ(refused.exitCode, 1) << refused.output;
  EXPECT_NE(refused.output.find("colmap.log"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("depth.fallback"), std::string::npos) << refused.output;
  ASSERT_EQ(fallback.exitCode, 0) << fallback.output;
  EXPECT_NE(fallback.output.find("using the manual depth layers"), std::string::npos)
      << fallback.output;
  EXPECT_EQ(countFiles(out, ".png"), size_t(kFrames));  // all from the fallback run
}

TEST_F(CliDepthColmap, TripodPanIsRefusedAsNoParallaxOrFallsBackToLayers) {
  const stdfs::path dir = test::freshTempDir("depth_colmap_pan");
  const std::string clip = writeClip(dir, pan());
  const stdfs::path out = dir / "out";
  stdfs::create_directories(out);
  auto refused = test::runPluvia(renderArgs(clip, out, {}));
  EXPECT_EQ(refused.exitCode, 1) << refused.output;
  EXPECT_NE(refused.output.find("pan or a tripod"), std::string::npos) << refused.output;
  EXPECT_EQ(countFiles(out, ".png"), 0u);

  auto fallback = test::runPluvia(renderArgs(clip, out, {"depth.fallback=layers"}));
  ASSERT_EQ(fallback.exitCode, 0) << fallback.output;
  EXPECT_NE(fallback.output.find("pan or a tripod"), std::string::npos) << fallback.output;
  EXPECT_EQ(countFiles(out, ".png"), size_t(kFrames));
}

}  // namespace
}  // namespace pluvia
