// `pluvia bench` refuses a malformed --strokes, --lod or --size before it measures anything: a
// usage error (exit 2) that quotes the option and the bad item; a movie bench runs and cleans up.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "test_support.h"
#include "util/subprocess.h"

using namespace pluvia::test;

namespace {

struct BadArgs {
  std::vector<std::string> args;
  std::string mentions;
};

class CliBenchArgs : public ::testing::TestWithParam<BadArgs> {};

TEST_P(CliBenchArgs, RefusedWithUsageError) {
  std::vector<std::string> args = {"bench"};
  args.insert(args.end(), GetParam().args.begin(), GetParam().args.end());
  const CommandResult r = runPluvia(args);
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find(GetParam().mentions), std::string::npos)
      << "expected '" << GetParam().mentions << "' in:\n"
      << r.output;
}

// A bench that fails (here a clip that does not exist) leaves no temporary folder behind.
TEST(CliBench, AFailedBenchLeavesNoTemporaryFolder) {
  const std::filesystem::path tmp = freshTempDir("bench_failure_tmp");
  const pluvia::ProcessResult r =
      pluvia::runProcess({"env", "TMPDIR=" + tmp.string(), pluviaBinary().string(), "bench",
                          (tmp / "missing.mp4").string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("missing.mp4"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::is_empty(tmp)) << "left in " << tmp;
}

// The movie bench renders twice into one cache, cold then warm, and prints both against x264
// alone; the temporary folder (the renders, the cache) goes with it.
TEST(CliBench, AMovieBenchRendersColdThenWarmAndCleansUp) {
  const std::filesystem::path tmp = freshTempDir("bench_movie_tmp");
  const pluvia::ProcessResult r =
      pluvia::runProcess({"env", "TMPDIR=" + tmp.string(), pluviaBinary().string(), "bench",
                          exampleClip().string(), "--frames", "2", "-p", "drizzle"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"bench: 2 frames of", "a fresh --cache), warm",
                             "ratio pluvia / encode only:", "(warm "});
  EXPECT_TRUE(std::filesystem::is_empty(tmp)) << "left in " << tmp;
}

INSTANTIATE_TEST_SUITE_P(
    Lists, CliBenchArgs,
    ::testing::Values(
        // Not a whole number, out of range, or nothing at all.
        BadArgs{{"--strokes", "1000,1e3"},
                "--strokes takes counts from 1 to 10000000 separated by commas, got '1e3'"},
        BadArgs{{"--strokes", "0"}, "got '0'"},
        BadArgs{{"--strokes", "99999999999"}, "got '99999999999'"},
        BadArgs{{"--strokes", ","}, "got ''"},
        BadArgs{{"--lod", "0,0.5x"},
                "--lod takes pixel sizes from 0 to 10 separated by commas, got '0.5x'"},
        BadArgs{{"--lod", "0,11"}, "got '11'"},
        // --size: a side under the command's smallest, trailing text.
        BadArgs{{"--strokes", "10", "--size", "0x480"},
                "--size takes WIDTHxHEIGHT, e.g. 720x480, got '0x480'"},
        BadArgs{{"--lod", "0,1", "--size", "8x8"},
                "--size takes WIDTHxHEIGHT, e.g. 1920x1080, got '8x8'"},
        BadArgs{{"--lod", "0,1", "--size", "640x480px"}, "got '640x480px'"},
        BadArgs{{"--passes", "--size", "640"}, "got '640'"}));

}  // namespace
