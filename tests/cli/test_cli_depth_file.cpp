// depth.source = "file": a depth sequence written by `pluvia depth` from manual layers renders
// the same frames (within 1e-6, every channel, the depth AOV included) as those layers do
// directly; a movie plate's depth frames count from 0 and smaller files are resampled; a missing
// depth frame or an empty depth.file stops the render before any frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <OpenImageIO/imageio.h>

#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

// The ground, and a card 6 m away over the middle of the frame: the fog differs over it.
const std::string kLayers =
    R"(depth.layers=[{"type": "ground"}, )"
    R"({"type": "card", "distance_m": 6, "x0": 0.25, "x1": 0.75, "y0": 0.2, "y1": 0.9}])";

// A textured 96x64 plate, frames 1-3, as PNG.
std::string writePlate(const stdfs::path& dir) {
  return writePixelPlate(dir, 1, 3, 96, 64, [](float* p, int x, int y, int f) {
    p[0] = float((x * 5 + y * 3 + f) % 256) / 255.0f;
    p[1] = float((x * 2 + y * 7) % 256) / 255.0f;
    p[2] = float((x + y * 11) % 256) / 255.0f;
  });
}

// The largest difference between two files' samples (infinities equal to themselves).
double maxDifference(const stdfs::path& a, const stdfs::path& b) {
  const ExrPixels pa = readAllChannels(a), pb = readAllChannels(b);
  EXPECT_EQ(pa.channels, pb.channels) << a << " vs " << b;
  EXPECT_EQ(pa.samples.size(), pb.samples.size()) << a << " vs " << b;
  if (pa.samples.size() != pb.samples.size()) return INFINITY;
  double largest = 0.0;
  for (size_t i = 0; i < pa.samples.size(); ++i) {
    if (pa.samples[i] == pb.samples[i]) continue;  // inf == inf
    largest = std::max(largest, std::fabs(double(pa.samples[i]) - double(pb.samples[i])));
  }
  return largest;
}

double meanDifference(const stdfs::path& a, const stdfs::path& b) {
  const Image ia = readImageFile(a), ib = readImageFile(b);
  double sum = 0.0;
  for (size_t i = 0; i < ia.rgba.size(); ++i) sum += std::fabs(ia.rgba[i] - ib.rgba[i]);
  return sum / double(ia.rgba.size());
}

size_t countFiles(const stdfs::path& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& e : stdfs::directory_iterator(dir)) ++n;
  return n;
}

// The plate's depth from kLayers, written by `pluvia depth` as dir/depth/z.####.exr (its
// pattern is returned), and dir/out/ made for the renders.
std::string writeLayerDepth(const stdfs::path& dir, const std::string& plate) {
  stdfs::create_directories(dir / "depth");
  stdfs::create_directories(dir / "out");
  const std::string depth = (dir / "depth" / "z.####.exr").string();
  auto written = runPluvia({"depth", plate, "-o", depth, "-p", "moderate", "--set", kLayers});
  // Thrown, the failure ends the test (gtest reports it with the message).
  if (written.exitCode != 0) throw std::runtime_error("pluvia depth failed: " + written.output);
  return depth;
}

TEST(CliDepthFile, TheDepthAovWritesTheSkyFiniteAndReadsItBackAsSky) {
  // All sky (depth.source none): the depth AOV holds 65504 m, the largest half float, never
  // +inf, which a compositor's ZDefocus and filters cannot take; given back as depth.file, that
  // value is sky again, and the frame is the all-sky render's.
  const auto dir = freshTempDir("depth_file_sky");
  const std::string plate = writePlate(dir);
  auto sky =
      runPluvia({"render", plate, "-p", "moderate", "-o", (dir / "out" / "sky.####.exr").string(),
                 "--aov", "depth", "--set", "depth.source=none"});
  ASSERT_EQ(sky.exitCode, 0) << sky.output;
  const ExrPixels pixels = readAllChannels(dir / "out" / "sky.0001.exr");
  const auto z = std::find(pixels.channels.begin(), pixels.channels.end(), "depth.Z");
  ASSERT_NE(z, pixels.channels.end());
  const size_t channel = z - pixels.channels.begin(), stride = pixels.channels.size();
  for (size_t i = channel; i < pixels.samples.size(); i += stride)
    ASSERT_EQ(pixels.samples[i], 65504.0f) << "sample " << i;

  auto back =
      runPluvia({"render", plate, "-p", "moderate", "-o", (dir / "out" / "back.####.exr").string(),
                 "--frames", "1-1", "--aov", "depth", "--set", "depth.source=file", "--set",
                 "depth.file=" + (dir / "out" / "sky.####.exr").string()});
  ASSERT_EQ(back.exitCode, 0) << back.output;
  EXPECT_LE(maxDifference(dir / "out" / "sky.0001.exr", dir / "out" / "back.0001.exr"), 1e-6);
}

}  // namespace

TEST(CliDepthFile, RendersAsTheLayersItWasWrittenFrom) {
  const auto dir = freshTempDir("depth_file_same");
  const std::string plate = writePlate(dir);
  const std::string depth = writeLayerDepth(dir, plate);

  auto layers = runPluvia({"render", plate, "-p", "moderate", "-o",
                           (dir / "out" / "layers.####.exr").string(), "--aov", "depth", "--set",
                           "depth.source=layers", "--set", kLayers});
  ASSERT_EQ(layers.exitCode, 0) << layers.output;
  auto file =
      runPluvia({"render", plate, "-p", "moderate", "-o", (dir / "out" / "file.####.exr").string(),
                 "--aov", "depth", "--set", "depth.source=file", "--set", "depth.file=" + depth});
  ASSERT_EQ(file.exitCode, 0) << file.output;
  // An EXR output holds the AOVs as channels: "depth.Z" beside R, G, B (the plate has no
  // alpha, and none is invented).
  EXPECT_EQ(readAllChannels(dir / "out" / "file.0001.exr").channels,
            (std::vector<std::string>{"R", "G", "B", "depth.Z"}));
  for (const char* frame : {"0001", "0002", "0003"}) {
    EXPECT_LE(maxDifference(dir / "out" / ("layers." + std::string(frame) + ".exr"),
                            dir / "out" / ("file." + std::string(frame) + ".exr")),
              1e-6)
        << "frame " << frame;
  }

  // The comparison means something: without the card and the ground (all sky) the frame
  // differs.
  auto sky =
      runPluvia({"render", plate, "-p", "moderate", "-o", (dir / "out" / "sky.####.exr").string(),
                 "--frames", "1-1", "--set", "depth.source=none"});
  ASSERT_EQ(sky.exitCode, 0) << sky.output;
  EXPECT_GT(meanDifference(dir / "out" / "sky.0001.exr", dir / "out" / "file.0001.exr"), 1e-3);
}

TEST(CliDepthFile, MoviePlateFramesCountFromZeroAndSmallerFilesAreResampled) {
  // One 16x12 file per frame of the 48-frame example movie, frame f uniformly 4 + f metres (in R
  // of an RGB EXR), resampled to 768x576: output frame f's depth AOV is 4 + f everywhere.
  const auto dir = freshTempDir("depth_file_movie");
  stdfs::create_directories(dir / "out");
  for (int f = 0; f < 48; ++f) {
    Image depth(16, 12);
    for (size_t i = 0; i < depth.pixelCount(); ++i) depth.rgba[i * 4] = 4.0f + f;
    char name[64];
    std::snprintf(name, sizeof name, "d.%04d.exr", f);
    writeImageFile(dir / name, depth);
  }
  auto r = runPluvia({"render", exampleClip().string(), "-p",
                      (sourceDir() / "examples/street/street.json").string(), "-o",
                      (dir / "out" / "rain.####.exr").string(), "--frames", "5-6", "--aov", "depth",
                      "--set", "depth.source=file", "--set",
                      "depth.file=" + (dir / "d.%04d.exr").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (int f : {5, 6}) {
    char name[64];
    std::snprintf(name, sizeof name, "rain.%04d.exr", f);
    const ExrPixels pixels = readAllChannels(dir / "out" / name);
    const auto z = std::find(pixels.channels.begin(), pixels.channels.end(), "depth.Z");
    ASSERT_NE(z, pixels.channels.end()) << name;
    const size_t channel = z - pixels.channels.begin(), stride = pixels.channels.size();
    double largest = 0.0;
    for (size_t i = channel; i < pixels.samples.size(); i += stride)
      largest = std::max(largest, std::fabs(pixels.samples[i] - (4.0 + f)));
    EXPECT_LE(largest, 1e-6 * (4.0 + f)) << name;
  }
}

TEST(CliDepthFile, MissingDepthFrameStopsBeforeAnyFrame) {
  const auto dir = freshTempDir("depth_file_missing");
  const std::string plate = writePlate(dir);
  const std::string depth = writeLayerDepth(dir, plate);
  const stdfs::path deleted = dir / "depth" / "z.0002.exr";
  ASSERT_TRUE(stdfs::remove(deleted));

  auto missing =
      runPluvia({"render", plate, "-p", "moderate", "-o", (dir / "out" / "rain.####.exr").string(),
                 "--set", "depth.source=file", "--set", "depth.file=" + depth});
  EXPECT_EQ(missing.exitCode, 1) << missing.output;
  EXPECT_NE(missing.output.find(deleted.string()), std::string::npos) << missing.output;
  EXPECT_EQ(countFiles(dir / "out"), 0u) << missing.output;

  // depth.source = "file" without depth.file: refused, naming the key.
  auto empty = runPluvia({"render", plate, "-p", "moderate", "-o",
                          (dir / "out" / "rain.####.exr").string(), "--set", "depth.source=file"});
  EXPECT_EQ(empty.exitCode, 1) << empty.output;
  EXPECT_NE(empty.output.find("depth.file is empty"), std::string::npos) << empty.output;
  EXPECT_EQ(countFiles(dir / "out"), 0u) << empty.output;
}
