// Inputs past any sensible bound are refused with a message that names them, before any work:
// a chain of 100 presets each extending the next (30,000 overflowed the stack), and
// `farm assemble --fps 1e308` (accepted, then failed inside ffmpeg as "0/1001").
#include <gtest/gtest.h>

#include <fstream>

#include "test_support.h"

using namespace pluvia::test;
namespace stdfs = std::filesystem;

TEST(CliBounds, AnExtendsChainDeeperThan64IsRefused) {
  const stdfs::path dir = freshTempDir("bounds_extends");
  constexpr int kChain = 100;
  for (int i = 0; i < kChain; ++i) {
    std::ofstream out(dir / ("p" + std::to_string(i) + ".json"));
    if (i + 1 < kChain)
      out << R"({"pluvia": 1, "extends": "p)" << i + 1 << R"(.json"})";
    else
      out << R"({"pluvia": 1, "extends": "moderate"})";
  }
  const auto deep = runPluvia({"validate", (dir / "p0.json").string()});
  EXPECT_EQ(deep.exitCode, 1) << deep.output;
  EXPECT_NE(deep.output.find("\"extends\" chains more than 64 presets"), std::string::npos)
      << deep.output;
  // A chain of a few is fine.
  const auto shallow = runPluvia({"validate", (dir / "p97.json").string()});
  EXPECT_EQ(shallow.exitCode, 0) << shallow.output;
}

TEST(CliBounds, AssembleRefusesAFrameRateOutOfRange) {
  const stdfs::path dir = freshTempDir("bounds_fps");
  const auto r =
      runPluvia({"farm", "assemble", (dir / "f.####.png").string(), "-o", (dir / "m.mp4").string(),
                 "--fps", "1e308", "--frames", "1-6", "-p", "moderate"});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("--fps"), std::string::npos) << r.output;
  EXPECT_FALSE(stdfs::exists(dir / "m.mp4"));
}
