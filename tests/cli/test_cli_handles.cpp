// Rain tied to absolute frame numbers: a plate re-delivered with other handles (starting at 1003
// instead of 1001) gets the same rain on the same frame numbers, since the simulation starts at
// rain.start_frame whatever frame the plate starts at; and frames rendered in chunks are the
// frames of the whole run.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

// A still plate (the same picture on every frame, as a locked-off shot), frames first..last:
// a bright sky over a textured dark ground, so the rain shows.
std::string writeStillPlate(const stdfs::path& dir, int first, int last) {
  return writePixelPlate(dir, first, last, 160, 120, [](float* p, int x, int y, int) {
    const float texture = ((x / 8 + y / 8) % 2) ? 0.06f : 0.1f;
    for (int c = 0; c < 3; ++c) p[c] = y < 40 ? 0.9f : texture;
  });
}

std::string frameName(const std::string& stem, int frame) {
  char name[64];
  std::snprintf(name, sizeof name, "%s.%04d.png", stem.c_str(), frame);
  return name;
}

double meanAbsDifference(const Image& a, const Image& b) {
  double sum = 0;
  for (size_t i = 0; i < a.rgba.size(); ++i) sum += std::abs(a.rgba[i] - b.rgba[i]);
  return sum / double(a.rgba.size());
}

TEST(CliHandles, TrimmedPlateGetsTheSameRainOnTheSameFrames) {
  const stdfs::path longDir = freshTempDir("handles_long"),
                    shortDir = freshTempDir("handles_short");
  const std::string longPlate = writeStillPlate(longDir, 1001, 1006);
  const std::string shortPlate = writeStillPlate(shortDir, 1003, 1006);
  const stdfs::path out = freshTempDir("handles_out");
  const auto render = [&](const std::string& plate, const std::string& stem,
                          std::vector<std::string> extra) {
    // Drawn to 8 m: at 160 px the camera's own depth (0.6 m) holds too few drops to tell two
    // starts of the simulation apart.
    std::vector<std::string> args{"-q",
                                  "render",
                                  plate,
                                  "-p",
                                  "moderate",
                                  "-o",
                                  (out / (stem + ".####.png")).string(),
                                  "--set",
                                  "rain.far_m=8"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = runPluvia(args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
  };
  render(longPlate, "long", {});
  render(shortPlate, "short", {});
  // The same as chunks: 1003-1004 and 1005-1006 of the long plate alone.
  render(longPlate, "chunk", {"--frames", "1003-1004"});
  render(longPlate, "chunk", {"--frames", "1005-1006"});
  // Starting the simulation at the trimmed plate's first frame gives other rain: the test can
  // fail.
  render(shortPlate, "fromClip", {"--set", "rain.start_frame=1003"});
  for (int f = 1003; f <= 1006; ++f) {
    const Image whole = readImageFile(out / frameName("long", f));
    const Image trimmed = readImageFile(out / frameName("short", f));
    const Image chunked = readImageFile(out / frameName("chunk", f));
    ASSERT_EQ(whole.rgba.size(), trimmed.rgba.size());
    EXPECT_TRUE(whole.rgba == trimmed.rgba) << "frame " << f;
    EXPECT_TRUE(whole.rgba == chunked.rgba) << "frame " << f;
    const Image other = readImageFile(out / frameName("fromClip", f));
    EXPECT_GT(meanAbsDifference(whole, other), 1e-4) << "frame " << f;
  }
}

}  // namespace
