// End-to-end: the facility's ways in and out (issue 19): "@" patterns and stepped frame lists,
// deep movie input, ProRes/DNxHR output with colour tags, EXR options and pass-through, OCIO
// configs, and the log a wrangler reads.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "test_support.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

// A small textured plate sequence, frames first..last, written as PNG.
std::string writePlate(const stdfs::path& dir, int first, int last, int w = 64, int h = 36) {
  return test::writePlateSequence(dir, first, last, w, h, [](Image& image, int f) {
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x) {
        float* p = image.pixel(x, y);
        p[0] = float((x * 7 + y * 3 + f) % 256) / 255.0f;
        p[1] = float((x * 2 + y * 5) % 256) / 255.0f;
        p[2] = float((x + y * 11) % 256) / 255.0f;
      }
  });
}

// "dir/plate.####.png" -> "dir/plate.@@@@.png"
std::string withAtSigns(std::string pattern) {
  for (char& c : pattern)
    if (c == '#') c = '@';
  return pattern;
}

}  // namespace

TEST(CliIo, AtPatternsAndASteppedFrameList) {
  auto dir = freshTempDir("cli_io_stepped");
  const std::string plate = withAtSigns(writePlate(dir, 1001, 1009));
  const std::string out = (dir / "out.@@@@.png").string();
  auto r = runPluvia({"render", plate, "-p", "drizzle", "-o", out, "--frames", "1001-1009x4",
                      "--set", "rain.enabled=false"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (int f = 1001; f <= 1009; ++f) {
    const bool asked = (f - 1001) % 4 == 0;
    EXPECT_EQ(stdfs::exists(dir / ("out." + std::to_string(f) + ".png")), asked) << f;
  }
  // Rain off: each frame written is its own plate frame (not the 1st, 2nd, 3rd of the clip).
  Image written = readImageFile(dir / "out.1005.png");
  Image source = readImageFile(dir / "plate.1005.png");
  double difference = 0;
  for (size_t i = 0; i < written.rgba.size(); ++i)
    difference += std::abs(written.rgba[i] - source.rgba[i]);
  EXPECT_LT(difference / written.rgba.size(), 1.0 / 255);
}

TEST(CliIo, CommaListNamesAFrameTheClipLacks) {
  auto dir = freshTempDir("cli_io_comma");
  const std::string plate = writePlate(dir, 1, 3);
  auto r = runPluvia(
      {"render", plate, "-p", "drizzle", "-o", (dir / "o.####.png").string(), "--frames", "1,3,7"});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("frame 7 of --frames is not in"), std::string::npos) << r.output;
  EXPECT_FALSE(stdfs::exists(dir / "o.0001.png"));
  r = runPluvia(
      {"render", plate, "-p", "drizzle", "-o", (dir / "o.####.png").string(), "--frames", "1-3x0"});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("'1-3x0'"), std::string::npos) << r.output;
}
