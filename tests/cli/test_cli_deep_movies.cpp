// A 10-bit movie through a render with every stage off comes back as it went in (issue 59: a
// ProRes 422 HQ grey ramp came back 0.38 % dark, Y' 864 -> 861, and clipped to 64-940).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

#include "test_support.h"
#include "util/subprocess.h"

using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

constexpr int kWidth = 256, kHeight = 4;

// Y' codes 4 to 1019 across the frame: sub-blacks, the nominal range 64-940, super-whites.
std::vector<int> rampCodes() {
  std::vector<int> codes;
  for (int x = 0; x < kWidth; ++x) codes.push_back(4 + (1019 - 4) * x / (kWidth - 1));
  return codes;
}

// The first frame's Y' row 2 as 10-bit codes.
std::vector<int> lumaCodes(const stdfs::path& movie) {
  const pluvia::ProcessResult decoded =
      pluvia::runProcess({"sh", "-c",
                          "ffmpeg -v error -i \"$0\" -frames:v 1 -f rawvideo -pix_fmt "
                          "yuv422p10le - | od -An -v -tu2 -w2",
                          movie.string()});
  std::vector<int> values;
  for (size_t at = 0; at < decoded.output.size();) {
    char* end = nullptr;
    const long value = std::strtol(decoded.output.c_str() + at, &end, 10);
    if (end == decoded.output.c_str() + at) break;
    values.push_back(int(value));
    at = size_t(end - decoded.output.c_str());
  }
  if (values.size() < size_t(kWidth) * 3) return {};
  return {values.begin() + 2 * kWidth, values.begin() + 3 * kWidth};
}

}  // namespace

TEST(CliDeepMovies, ATenBitRampRoundTripsThroughARenderWithEveryStageOff) {
  if (!pluvia::programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  const stdfs::path dir = freshTempDir("deep_movie_ramp");
  std::vector<uint16_t> planes;
  const std::vector<int> codes = rampCodes();
  for (int y = 0; y < kHeight; ++y)
    for (int code : codes) planes.push_back(uint16_t(code));
  planes.insert(planes.end(), size_t(kWidth) * kHeight, uint16_t(512));  // neutral Cb, Cr
  const stdfs::path raw = dir / "ramp.yuv", plate = dir / "ramp.mov", out = dir / "out.mov";
  std::ofstream(raw, std::ios::binary)
      .write(reinterpret_cast<const char*>(planes.data()),
             static_cast<std::streamsize>(planes.size() * sizeof(uint16_t)));
  const pluvia::ProcessResult made = pluvia::runProcess({"ffmpeg",      "-v",
                                                         "error",       "-f",
                                                         "rawvideo",    "-pix_fmt",
                                                         "yuv422p10le", "-s",
                                                         "256x4",       "-r",
                                                         "24",          "-i",
                                                         raw.string(),  "-frames:v",
                                                         "2",           "-c:v",
                                                         "prores_ks",   "-profile:v",
                                                         "3",           "-color_range",
                                                         "tv",          "-colorspace",
                                                         "bt709",       "-color_trc",
                                                         "bt709",       "-color_primaries",
                                                         "bt709",       plate.string()});
  ASSERT_EQ(made.exitCode, 0) << made.output;
  ASSERT_EQ(lumaCodes(plate), codes) << "the plate holds the ramp";
  const auto r = runPluvia({"render", plate.string(), "-p", "base", "--set", "rain.enabled=false",
                            "--set", "wet_ground.enabled=false", "--set", "splash.enabled=false",
                            "--set", "lights.enabled=false", "--set", "rainbow.enabled=false",
                            "--codec", "prores_422hq", "-o", out.string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const std::vector<int> back = lumaCodes(out);
  ASSERT_EQ(back.size(), codes.size());
  // Every code comes back within 1, the super-whites and sub-blacks too (measured: all exact).
  for (int x = 0; x < kWidth; ++x) EXPECT_NEAR(back[size_t(x)], codes[size_t(x)], 1) << "x " << x;
  EXPECT_EQ(back.front(), 4);
  EXPECT_EQ(back.back(), 1019);
}
