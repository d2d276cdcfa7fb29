// --log FILE that cannot be written to the end (a full disk: /dev/full takes the open and fails
// every write) is said on stderr, and the command exits 1 although its frames are written: a
// farm asked for that log. A --set key with an empty part is blamed on --set, not on the preset.
#include <gtest/gtest.h>

#include "test_support.h"

using namespace pluvia::test;
namespace stdfs = std::filesystem;

TEST(CliLogFile, AFullLogDeviceIsSaidAndFailsTheCommand) {
  if (!stdfs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const stdfs::path dir = freshTempDir("log_full");
  const auto r =
      runPluvia({"render", exampleClip().string(), "-p", "drizzle", "-o",
                 (dir / "r.####.png").string(), "--frames", "0-0", "--log", "/dev/full"});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("the log file /dev/full stops here: No space left on device"),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(stdfs::exists(dir / "r.0000.png"));
}

TEST(CliLogFile, AnEmptyKeyInSetIsBlamedOnSet) {
  const auto r = runPluvia({"validate", "moderate", "--set", "rain..rate_mm_h=1"});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("--set rain..rate_mm_h: an empty key between dots"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("presets/moderate.json"), std::string::npos) << r.output;
}
