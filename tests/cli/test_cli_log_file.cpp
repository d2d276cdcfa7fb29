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
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("--set rain..rate_mm_h: an empty key between dots"), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("presets/moderate.json"), std::string::npos) << r.output;
}

// A value a --set gives that the schema refuses is the command line's mistake too: exit 2, the
// argument named, the shipped preset not blamed; a mistake in the file itself still names it.
TEST(CliLogFile, ABadValueInSetIsBlamedOnSet) {
  for (const std::string set : {"rain.rate_mm_h=abc", "rain.nokey=3", "rain.rate_mm_h=-5"}) {
    const auto r = runPluvia({"validate", "heavy", "--set", set});
    EXPECT_EQ(r.exitCode, 2) << r.output;
    EXPECT_NE(r.output.find("invalid --set:\n  --set " + set + ": /rain/"), std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("heavy.json"), std::string::npos) << r.output;
  }
  const auto dir = freshTempDir("set_blame");
  const auto preset = writeTextFile(dir, "p.json", R"({"pluvia": 1, "rain": {"rate_mm_h": "x"}})");
  const auto file = runPluvia({"validate", preset.string(), "--set", "fog.density=0.01"});
  EXPECT_EQ(file.exitCode, 1) << file.output;
  EXPECT_NE(file.output.find("invalid preset " + preset.string()), std::string::npos)
      << file.output;
}
