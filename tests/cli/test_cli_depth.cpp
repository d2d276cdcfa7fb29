// `pluvia depth`: manual depth layers written as single-channel float EXRs, and the COLMAP
// source's failure path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {
const std::string kExamplePreset = (sourceDir() / "examples/street/street.json").string();

// The example's camera (street.json): 50 degrees wide, 28 degrees down, 9 m up. The ground's
// z-depth at row y: the pixel's ray (z = -1) drops sin(tilt) + cos(tilt) * (y + 0.5 - cy) / f
// per metre of z-depth, whatever the column.
double groundDepth(int width, int height, int y) {
  const double tilt = 28 * M_PI / 180, heightMeters = 9;
  const double focalPx = 0.5 * width / std::tan(0.5 * 50 * M_PI / 180);
  const double below = (y + 0.5 - 0.5 * height) / focalPx;
  return heightMeters / (std::sin(tilt) + std::cos(tilt) * below);
}

size_t countFiles(const stdfs::path& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& e : stdfs::directory_iterator(dir)) ++n;
  return n;
}
}  // namespace

TEST(CliDepth, WritesTheGroundAndAKeyframedCardPerFrame) {
  auto dir = freshTempDir("depth_layers");
  auto r = runPluvia({"depth", exampleClip().string(), "-o", (dir / "z.####.exr").string(),
                      "--source", "layers", "-p", kExamplePreset, "--frames", "0-2", "--set",
                      "depth.layers.1.distance_m=[[0,60],[2,80]]"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(countFiles(dir), 3u);  // three frames, no temporary files left
  for (int frame = 0; frame <= 2; ++frame) {
    auto path = dir / ("z.000" + std::to_string(frame) + ".exr");
    ASSERT_TRUE(stdfs::exists(path)) << path;
    Image z = readImageFile(path);  // one channel: R = G = B = Z
    const int w = z.width, h = z.height;
    for (auto [x, y] : {std::pair{w / 2, h / 2}, std::pair{w / 10, h - 1},
                        std::pair{w - 3, 3 * h / 4}, std::pair{w / 3, h / 3}}) {
      const double expected = groundDepth(w, h, y);
      EXPECT_NEAR(z.rgba[(size_t(y) * w + x) * 4], expected, 1e-3 * expected)
          << "frame " << frame << " pixel " << x << "," << y;
    }
    // The card over the top 17 % of the frame goes from 60 m to 80 m over frames 0-2.
    EXPECT_FLOAT_EQ(z.rgba[(size_t(2) * w + w / 2) * 4], 60.0f + 10.0f * frame);
  }
}

TEST(CliDepth, BadPresetOrOutputWritesNothing) {
  auto dir = freshTempDir("depth_bad");
  auto out = (dir / "z.####.exr").string();
  auto bad = runPluvia({"depth", exampleClip().string(), "-o", out, "-p", kExamplePreset,
                        "--frames", "0-2", "--set", "depth.layers.1.distanse_m=40"});
  EXPECT_EQ(bad.exitCode, 2) << bad.output;  // the command line's mistake, not the file's
  EXPECT_NE(bad.output.find("--set depth.layers.1.distanse_m=40: /depth/layers/1/distanse_m: "
                            "unknown key"),
            std::string::npos)
      << bad.output;
  EXPECT_EQ(bad.output.find("street.json"), std::string::npos) << bad.output;
  auto polygon =
      runPluvia({"depth", exampleClip().string(), "-o", out, "-p", kExamplePreset, "--set",
                 R"(depth.layers=[{"type": "polygon", "points": [[0, 0], [1, 1]]}])"});
  EXPECT_EQ(polygon.exitCode, 2) << polygon.output;
  EXPECT_NE(polygon.output.find("/depth/layers/0/points: expected [[x, y], ...]"),
            std::string::npos)
      << polygon.output;
  auto notExr = runPluvia({"depth", exampleClip().string(), "-o", (dir / "z.####.png").string()});
  EXPECT_EQ(notExr.exitCode, 2) << notExr.output;
  auto range = runPluvia({"depth", exampleClip().string(), "-o", out, "--frames", "46-60"});
  EXPECT_EQ(range.exitCode, 2) << range.output;
  EXPECT_NE(range.output.find("frame 48 is not in"), std::string::npos) << range.output;
  EXPECT_EQ(countFiles(dir), 0u);
}

TEST(CliDepth, StaticRealPlateIsRefusedAsNoParallaxBeforeColmapRuns) {
  // The example plate is shot from a tripod: the parallax check refuses it (structure from motion
  // would give no depth) before COLMAP runs (a colmap that cannot run proves it never starts),
  // and no depth frame is written.
  auto dir = freshTempDir("depth_colmap_static");
  const std::string out = (dir / "z.####.exr").string();
  ::setenv("PLUVIA_COLMAP", "/nonexistent/colmap", 1);
  auto colmap = runPluvia(
      {"depth", exampleClip().string(), "-o", out, "--source", "colmap", "--frames", "0-2"});
  ::unsetenv("PLUVIA_COLMAP");
  EXPECT_EQ(colmap.exitCode, 1) << colmap.output;
  EXPECT_NE(colmap.output.find("pan or a tripod"), std::string::npos) << colmap.output;
  EXPECT_NE(colmap.output.find("--source layers"), std::string::npos) << colmap.output;
  EXPECT_EQ(colmap.output.find("feature_extractor"), std::string::npos) << colmap.output;
  for (const auto& entry : stdfs::recursive_directory_iterator(dir))
    EXPECT_NE(entry.path().extension(), ".exr") << entry.path();
}

TEST(CliDepth, TooFewFramesAreRefusedBeforeColmapRuns) {
  auto dir = freshTempDir("depth_colmap_two_frames");
  ::setenv("PLUVIA_COLMAP", "/nonexistent/colmap", 1);
  auto two = runPluvia({"depth", exampleClip().string(), "-o", (dir / "z.####.exr").string(),
                        "--source", "colmap", "--frames", "0-1"});
  ::unsetenv("PLUVIA_COLMAP");
  EXPECT_EQ(two.exitCode, 1) << two.output;
  EXPECT_NE(two.output.find("2 frames to track: camera tracking needs at least 3"),
            std::string::npos)
      << two.output;
  EXPECT_FALSE(stdfs::exists(dir / "colmap"));
}
