// The default depth's sky on a moving camera: the still (the median of frames spread over the
// clip) is a blend of views there, so each frame's own sky is found in it; a locked-off camera
// keeps the still's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/core.hpp>

#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;

namespace {

constexpr int kWidth = 320, kHeight = 240;

// A bright sky over buildings whose roofs step between rows 40 and 90 (both above the horizon
// of the default camera, row 120) every 100 px of the panorama, their walls striped with dark
// windows every 40 px. Frame f of a moving camera sees it from panorama column 60 f.
int roofRow(int panoramaX) {
  return (panoramaX / 100) % 2 == 0 ? 40 : 90;
}

void paintView(Image& image, int offsetPx) {
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const int px = x + offsetPx;
      float v = 0.92f;
      if (y >= roofRow(px)) v = (px % 40) < 14 && y % 30 < 18 ? 0.08f : 0.45f;
      for (int c = 0; c < 3; ++c) image.pixel(x, y)[c] = v;
    }
}

// Shares of frame `path`'s sky (above its roofs by 4 rows) and wall (below them by 4 rows,
// above the horizon) that the depth AOV gives as sky (65504 m).
std::pair<double, double> skyShares(const std::filesystem::path& path, int offsetPx) {
  const ExrPixels pixels = readAllChannels(path);
  const auto z = std::find(pixels.channels.begin(), pixels.channels.end(), "depth.Z");
  if (z == pixels.channels.end()) return {-1.0, -1.0};
  const size_t channel = size_t(z - pixels.channels.begin()), stride = pixels.channels.size();
  double sky = 0, skyAsSky = 0, wall = 0, wallAsSky = 0;
  for (int y = 0; y < 115; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const bool isSky = pixels.samples[(size_t(y) * kWidth + x) * stride + channel] >= 65504.0f;
      const int roof = roofRow(x + offsetPx);
      if (y < roof - 4) sky += 1, skyAsSky += isSky;
      if (y > roof + 4) wall += 1, wallAsSky += isSky;
    }
  return {skyAsSky / sky, wallAsSky / wall};
}

TEST(CliMovingSky, EachFrameOfAMovingCameraGetsItsOwnSky) {
  const auto dir = freshTempDir("cli_moving_sky");
  const std::string plate =
      writePlateSequence(dir, 1, 5, kWidth, kHeight,
                         [](Image& image, int frame) { paintView(image, 60 * (frame - 1)); });
  const CommandResult r = runPluvia({"render", plate, "-p", "moderate", "--set", "rain.rate_mm_h=0",
                                     "--aov", "depth", "-o", (dir / "out.####.exr").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"depth: guessed from each frame", "the camera moves"});
  // Measured: every frame's sky and none of its walls. With the still's sky (the rule before),
  // frames 1, 2 and 3 kept 94, 81 and 72 % of their sky, and frames 1 and 2 took 10 and 13 % of
  // their walls for sky.
  for (int f = 1; f <= 5; ++f) {
    const auto [sky, wall] = skyShares(dir / fmt::format("out.{:04d}.exr", f), 60 * (f - 1));
    EXPECT_GT(sky, 0.98) << "frame " << f;
    EXPECT_LT(wall, 0.01) << "frame " << f;
  }
}

TEST(CliMovingSky, ALockedOffCameraKeepsTheStillsSky) {
  const auto dir = freshTempDir("cli_locked_sky");
  const std::string plate = writePlateSequence(dir, 1, 5, kWidth, kHeight,
                                               [](Image& image, int) { paintView(image, 0); });
  const CommandResult r =
      runPluvia({"render", plate, "-p", "moderate", "--set", "rain.rate_mm_h=0", "--aov", "depth",
                 "--frames", "3", "-o", (dir / "out.####.exr").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"depth: guessed from the plate"});
  const auto [sky, wall] = skyShares(dir / "out.0003.exr", 0);
  EXPECT_GT(sky, 0.98);
  EXPECT_LT(wall, 0.01);
}

// Frame 3 of a pan catches a flat, bright patch on the wall below the left roofs (glare, a pale
// panel): on its own it reads as sky joined to the sky above. Its neighbours show the wall there,
// so the vote keeps it backdrop, and the rest of the sky stays sky.
TEST(CliMovingSky, APatchThatLooksLikeSkyInOneFrameOnlyStaysBackdrop) {
  const auto dir = freshTempDir("cli_moving_sky_vote");
  const cv::Rect patch(20, 50, 70, 50);
  const std::string plate =
      writePlateSequence(dir, 1, 5, kWidth, kHeight, [&](Image& image, int frame) {
        paintView(image, 13 * (frame - 1));
        if (frame != 3) return;
        for (int y = patch.y; y < patch.y + patch.height; ++y)
          for (int x = patch.x; x < patch.x + patch.width; ++x)
            for (int c = 0; c < 3; ++c) image.pixel(x, y)[c] = 0.92f;
      });
  const CommandResult r = runPluvia({"render", plate, "-p", "moderate", "--set", "rain.rate_mm_h=0",
                                     "--aov", "depth", "-o", (dir / "out.####.exr").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"voted with the frames beside it"});
  const ExrPixels pixels = readAllChannels(dir / "out.0003.exr");
  const auto z = std::find(pixels.channels.begin(), pixels.channels.end(), "depth.Z");
  ASSERT_NE(z, pixels.channels.end());
  const size_t channel = size_t(z - pixels.channels.begin()), stride = pixels.channels.size();
  double inPatch = 0, patchAsSky = 0;
  for (int y = patch.y; y < patch.y + patch.height; ++y)
    for (int x = patch.x; x < patch.x + patch.width; ++x) {
      if (y < roofRow(x + 26) + 4) continue;  // the patch below the roof only
      inPatch += 1;
      patchAsSky += pixels.samples[(size_t(y) * kWidth + x) * stride + channel] >= 65504.0f;
    }
  // Measured: none of it (each frame's own sky took it all). The sky above the roofs stays sky.
  EXPECT_LT(patchAsSky / inPatch, 0.05);
  EXPECT_GT(skyShares(dir / "out.0003.exr", 26).first, 0.95);
}

}  // namespace
