// What a render says at the default level: enough to know what ran and why, each thing once.
#include <filesystem>

#include <gtest/gtest.h>

#include "test_support.h"
#include "util/subprocess.h"

using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

size_t occurrences(const std::string& text, const std::string& needle) {
  size_t count = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1))
    ++count;
  return count;
}

}  // namespace

// A variable-rate movie was read by three readers, each warning; the plan took 30 lines; the
// splash stage said the rain's shutter again. Now: the warning once, the plan in one line (its
// notes and artifacts with -v), the shutter once.
TEST(CliQuietOutput, EachThingIsSaidOnceAndThePlanInOneLine) {
  if (!pluvia::programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  const stdfs::path dir = freshTempDir("quiet_output");
  const stdfs::path movie = dir / "vfr.mkv";
  const pluvia::ProcessResult made = pluvia::runProcess(
      {"ffmpeg", "-v", "error", "-f", "lavfi", "-i", "testsrc=s=96x64:r=10", "-frames:v", "12",
       "-vf", "setpts='(if(lt(N,6),N,6+(N-6)*2))/10/TB'", "-fps_mode", "vfr", "-c:v", "libx264",
       "-pix_fmt", "yuv420p", movie.string()});
  ASSERT_EQ(made.exitCode, 0) << made.output;
  const auto r = runPluvia({"render", movie.string(), "-p", "heavy", "--frames", "0-3", "-o",
                            (dir / "o.####.png").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(occurrences(r.output, "has a variable frame rate"), 1u) << r.output;
  EXPECT_EQ(occurrences(r.output, ": shutter 1/"), 1u) << r.output;
  EXPECT_NE(r.output.find("pluvia: plan: runs lighting, depth, "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("leaves out derain [nothing reads its output"), std::string::npos);
  EXPECT_EQ(r.output.find("artifacts (made by"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("preset (resolved)"), std::string::npos);
  // With -v the full plan is there too.
  const auto verbose = runPluvia({"render", movie.string(), "-p", "heavy", "--frames", "0-0", "-o",
                                  (dir / "v.####.png").string(), "-v"});
  ASSERT_EQ(verbose.exitCode, 0) << verbose.output;
  EXPECT_NE(verbose.output.find("artifacts (made by"), std::string::npos);
  EXPECT_NE(verbose.output.find("  skip    derain       nothing reads its output"),
            std::string::npos);
}
