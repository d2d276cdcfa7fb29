// The depth stage's COLMAP source in a render: clips of the synthetic street
// (lab/synthetic_scene.h) written as PNG sequences, tracked by the real colmap. A walk tracks,
// renders with the tracked camera, caches its tracking (plan: needed, then cached) and reuses it; a
// colmap that cannot run (naming its log) and a tripod pan (no parallax, found before COLMAP runs)
// stop the render before any frame, unless depth.fallback = layers, which renders with the manual
// layers and says why.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "lab/synthetic_scene.h"
#include "sfm/colmap_runner.h"
#include "sfm/dense_import.h"
#include "test_support.h"
#include "util/fs.h"

using namespace pluvia::sfm;

namespace pluvia {
namespace {

namespace stdfs = std::filesystem;

// 720p: at 320x180 and 640x360 COLMAP settles on a wrong solution for this ground-dominated walk
// (pluvia report depth), which the depth stage then refuses (no ground plane below the cameras).
constexpr int kWidth = 1280;
constexpr int kHeight = 720;
constexpr int kFrames = 12;

size_t countFiles(const stdfs::path& dir, const std::string& extension) {
  size_t n = 0;
  for (const auto& entry : stdfs::directory_iterator(dir))
    n += entry.path().extension() == extension ? 1 : 0;
  return n;
}

// Writes frames 1..kFrames of `keys` as dir/street.####.png; returns the sequence pattern. The
// true z-depth of frame N is appended to `trueDepth` (index N - 1) when given.
std::string writeClip(const stdfs::path& dir, const std::vector<lab::SyntheticPathKey>& keys,
                      std::vector<std::vector<float>>* trueDepth = nullptr) {
  lab::SyntheticSceneRenderer renderer(kWidth, kHeight);
  const lab::SyntheticView intrinsics = lab::defaultSyntheticIntrinsics(kWidth, kHeight);
  for (int i = 0; i < kFrames; ++i) {
    Image frame = renderer.render(lab::syntheticViewAt(intrinsics, keys[size_t(i)]));
    test::writeImageFile(dir / fmt::format("street.{:04d}.png", i + 1), frame);
    if (trueDepth) trueDepth->push_back(*frame.findPlane("depth"));
  }
  return (dir / "street.####.png").string();
}

// A walk: every 4th key of the default 48-frame path (0.2 m a frame down the street).
std::vector<lab::SyntheticPathKey> walk() {
  const auto path = lab::defaultSyntheticPath(48);
  std::vector<lab::SyntheticPathKey> keys;
  for (int i = 0; i < kFrames; ++i) keys.push_back(path[size_t(4 * i)]);
  return keys;
}

// A tripod pan: the first key's position, yaw from -6 to +5 degrees.
std::vector<lab::SyntheticPathKey> pan() {
  std::vector<lab::SyntheticPathKey> keys(kFrames, lab::defaultSyntheticPath(1)[0]);
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

  // Two frames are enough to show the tracking read from the cache (the suite's time).
  stdfs::remove_all(out);
  stdfs::create_directories(out);
  render.insert(render.end(), {"--frames", "1-2"});
  auto second = test::runPluvia(render);
  ASSERT_EQ(second.exitCode, 0) << second.output;
  EXPECT_NE(second.output.find("COLMAP tracking from cache"), std::string::npos) << second.output;
  EXPECT_EQ(second.output.find("COLMAP registered"), std::string::npos) << second.output;
  EXPECT_EQ(countFiles(out, ".png"), size_t(2));
}

TEST_F(CliDepthColmap, MissingColmapStopsBeforeAnyFrameUnlessFallbackAllowsLayers) {
  const stdfs::path dir = test::freshTempDir("depth_colmap_missing_render");
  const std::string clip = writeClip(dir, walk());
  const stdfs::path out = dir / "out";
  stdfs::create_directories(out);
  ::setenv("PLUVIA_COLMAP", "/nonexistent/colmap", 1);
  auto refused = test::runPluvia(renderArgs(clip, out, {}));
  auto fallback = test::runPluvia(renderArgs(clip, out, {"depth.fallback=layers"}));
  stdfs::create_directories(dir / "z");
  auto depth =
      test::runPluvia({"depth", clip, "-o", (dir / "z/z.####.exr").string(), "--source", "colmap"});
  ::unsetenv("PLUVIA_COLMAP");

  // pluvia depth names the step that failed and the log, which it keeps; no depth is written.
  EXPECT_EQ(depth.exitCode, 1) << depth.output;
  EXPECT_NE(depth.output.find("feature_extractor"), std::string::npos) << depth.output;
  EXPECT_NE(depth.output.find((dir / "z/colmap/colmap.log").string()), std::string::npos)
      << depth.output;
  EXPECT_TRUE(stdfs::exists(dir / "z/colmap/colmap.log"));
  EXPECT_EQ(countFiles(dir / "z", ".exr"), 0u);

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

TEST_F(CliDepthColmap, GivenModelIsReadAndDenseMapsReplaceTheDensifiedPoints) {
  // `pluvia depth --source colmap` keeps its workspace and model; a second run reads that model
  // (depth.colmap_model, no COLMAP) and imports a dense depth map for frame 5 in COLMAP's format
  // (here the true depth in model units, its left half a hole): the right half must come back
  // as the truth, the hole as the first run's densified depth.
  const stdfs::path dir = test::freshTempDir("depth_colmap_model");
  std::vector<std::vector<float>> truth;
  const std::string clip = writeClip(dir, walk(), &truth);
  stdfs::create_directories(dir / "z1");
  stdfs::create_directories(dir / "z2");
  const std::vector<std::string> sets{"--set", "camera.fov_deg=60", "--set", "camera.height_m=1.6"};
  std::vector<std::string> first{"depth",    clip,    "-o", (dir / "z1/z.####.exr").string(),
                                 "--source", "colmap"};
  first.insert(first.end(), sets.begin(), sets.end());
  auto tracked = test::runPluvia(first);
  ASSERT_EQ(tracked.exitCode, 0) << tracked.output;
  const auto poses = nlohmann::json::parse(fs::readTextFile(dir / "z1/colmap/poses.json"));
  const double metersPerUnit = poses.at("meters_per_model_unit").get<double>();
  ASSERT_GT(metersPerUnit, 0.0);

  const int frame = 5;
  ColmapArray map{kWidth, kHeight, 1, {}};
  for (size_t i = 0; i < truth[frame - 1].size(); ++i) {
    const float z = truth[frame - 1][i];
    const bool hole = int(i % kWidth) < kWidth / 2 || !std::isfinite(z);
    map.values.push_back(hole ? 0.0f : float(z / metersPerUnit));
  }
  const stdfs::path dense = dir / "dense";
  stdfs::create_directories(dense / "stereo/depth_maps");
  writeColmapArray(colmapDepthMapPath(dense, fmt::format("frame_{:08d}.png", frame)), map);

  std::vector<std::string> second{
      "depth",    clip,
      "-o",       (dir / "z2/z.####.exr").string(),
      "--source", "colmap",
      "--set",    "depth.colmap_model=" + (dir / "z1/colmap/model").string(),
      "--set",    "depth.colmap_dense=" + dense.string()};
  second.insert(second.end(), sets.begin(), sets.end());
  ::setenv("PLUVIA_COLMAP", "/nonexistent/colmap", 1);  // proves that COLMAP does not run
  auto imported = test::runPluvia(second);
  ::unsetenv("PLUVIA_COLMAP");
  ASSERT_EQ(imported.exitCode, 0) << imported.output;

  const Image densified = test::readImageFile(dir / "z1/z.0005.exr");
  const Image result = test::readImageFile(dir / "z2/z.0005.exr");
  int checked = 0;
  for (size_t i = 0; i < truth[frame - 1].size(); ++i) {
    const float z = result.rgba[4 * i], before = densified.rgba[4 * i];
    const float expected = map.values[i] > 0 ? truth[frame - 1][i] : before;
    if (!std::isfinite(expected)) {
      EXPECT_EQ(z, expected) << "pixel " << i;
      continue;
    }
    ASSERT_NEAR(z, expected, 1e-4 * expected) << "pixel " << i;
    ++checked;
  }
  EXPECT_GT(checked, kWidth * kHeight / 2);
  // Frames without a dense map keep the densified points exactly.
  const Image other1 = test::readImageFile(dir / "z1/z.0006.exr");
  const Image other2 = test::readImageFile(dir / "z2/z.0006.exr");
  EXPECT_EQ(other1.rgba, other2.rgba);
}

}  // namespace
}  // namespace pluvia
