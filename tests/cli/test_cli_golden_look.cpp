// The look's golden frames, as OpenImageIO's testsuite compares reference images: every shipped
// preset at its defaults renders frame 20 of the bundled example at half size, and the frame is
// compared with its reference in tests/golden/. An unintended change of the look (the shutter,
// the drops' light, the grading, the sky found) fails here; an intended one writes the new
// references with PLUVIA_UPDATE_GOLDEN=1 and commits them with the change that made them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "test_support.h"

using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

const std::vector<std::string> kShippedPresets = {"drizzle", "gentle", "moderate",
                                                  "hard",    "heavy",  "storm"};

// Off by at most this much on average (8-bit codes, each channel), and by more than kOffCodes
// in at most this share of the samples: rounding and the order of floating-point sums, not a
// changed look (streaks moved, lengthened or dimmed change every sample they cover by tens of
// codes: the rain covers 0.1-30 % of this frame).
constexpr double kMeanCodes = 0.5, kOffCodes = 8.0, kMaxOffShare = 0.0005;

class GoldenLook : public ::testing::TestWithParam<std::string> {};

TEST_P(GoldenLook, TheBundledExampleLooksAsItsReference) {
  const std::string preset = GetParam();
  const stdfs::path dir = freshTempDir("golden_" + preset);
  const auto rendered =
      runPluvia({"-q", "render", exampleClip().string(), "-p", preset, "--frames", "20-20",
                 "--proxy", "0.5", "--threads", "2", "-o", (dir / "frame.####.png").string()});
  ASSERT_EQ(rendered.exitCode, 0) << rendered.output;
  const cv::Mat frame = cv::imread((dir / "frame.0020.png").string());
  ASSERT_FALSE(frame.empty());
  const stdfs::path reference = sourceDir() / "tests/golden" / (preset + ".png");
  if (std::getenv("PLUVIA_UPDATE_GOLDEN")) {
    stdfs::create_directories(reference.parent_path());
    ASSERT_TRUE(cv::imwrite(reference.string(), frame));
    GTEST_SKIP() << "wrote " << reference;
  }
  const cv::Mat expected = cv::imread(reference.string());
  ASSERT_FALSE(expected.empty()) << reference << " is missing: PLUVIA_UPDATE_GOLDEN=1 writes it";
  ASSERT_EQ(frame.size(), expected.size());
  cv::Mat difference;
  cv::absdiff(frame, expected, difference);
  double sum = 0.0;
  size_t off = 0, samples = 0;
  for (auto it = difference.begin<uchar>(); it != difference.end<uchar>(); ++it, ++samples) {
    sum += *it;
    off += *it > kOffCodes;
  }
  const std::string where = " (" + (dir / "frame.0020.png").string() + " against " +
                            reference.string() + ": the look changed)";
  EXPECT_LE(sum / double(samples), kMeanCodes) << preset << where;
  EXPECT_LE(double(off) / double(samples), kMaxOffShare) << preset << where;
}

INSTANTIATE_TEST_SUITE_P(ShippedPresets, GoldenLook, ::testing::ValuesIn(kShippedPresets),
                         [](const auto& info) { return info.param; });

}  // namespace
