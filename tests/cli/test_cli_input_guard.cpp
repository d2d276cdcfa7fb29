// No file a run writes may be one of its inputs, whatever option names it (adversarial S11, S12):
// an AOV's own file, derain's --report, the --log (a report's --csv goes through the same atomic
// writer: tests/util/test_guarded_files.cpp). Each case wrote over the plate before; each now
// fails with the file named and leaves the input as it was.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "test_support.h"
#include "util/fs.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

std::string frameFile(const std::string& prefix, int frame) {
  char name[16];
  std::snprintf(name, sizeof name, ".%04d.png", frame);
  return prefix + name;
}

// Copies the frames of writeTexturedPlate(from, ...) under another prefix in `dir`.
std::string copyPlate(const stdfs::path& from, const stdfs::path& dir, const std::string& prefix,
                      int frames) {
  for (int f = 1; f <= frames; ++f)
    stdfs::copy_file(from / frameFile("plate", f), dir / frameFile(prefix, f));
  return (dir / (prefix + ".####.png")).string();
}

}  // namespace

TEST(CliInputGuard, AnAovFileIsNeverWrittenOverThePlate) {
  const stdfs::path dir = freshTempDir("guard_aov");
  stdfs::create_directories(dir / "src");
  writeTexturedPlate(dir / "src", 1, 3);
  // The plate is named as the rain AOV of "street.####.png" would be.
  const std::string rained = copyPlate(dir / "src", dir, "street.rain", 3);
  const std::string before = fs::readTextFile(dir / "street.rain.0002.png");
  const auto r = runPluvia({"render", rained, "-p", "moderate", "-o",
                            (dir / "street.####.png").string(), "--aov", "rain"});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("street.rain.0001.png is the input file"), std::string::npos) << r.output;
  EXPECT_EQ(fs::readTextFile(dir / "street.rain.0002.png"), before);
  EXPECT_FALSE(stdfs::exists(dir / "street.0001.png"));  // refused before any work

  // A single image: still.matte.png is --aov matte's file for -o still.png.
  stdfs::copy_file(dir / "street.rain.0001.png", dir / "still.matte.png");
  const std::string still = fs::readTextFile(dir / "still.matte.png");
  const auto s = runPluvia({"render", (dir / "still.matte.png").string(), "-p", "moderate", "-o",
                            (dir / "still.png").string(), "--aov", "matte"});
  EXPECT_EQ(s.exitCode, 2) << s.output;
  EXPECT_EQ(fs::readTextFile(dir / "still.matte.png"), still);
}

TEST(CliInputGuard, ReportsAndTheLogAreNeverWrittenOverAnInput) {
  const stdfs::path dir = freshTempDir("guard_reports");
  const std::string plate = writeTexturedPlate(dir, 1, 4);
  const stdfs::path first = dir / "plate.0001.png", second = dir / "plate.0002.png";
  const std::string firstBytes = fs::readTextFile(first), secondBytes = fs::readTextFile(second);

  const auto derain = runPluvia(
      {"derain", plate, "-o", (dir / "d" / "c.####.png").string(), "--report", first.string()});
  EXPECT_NE(derain.exitCode, 0) << derain.output;
  EXPECT_NE(derain.output.find("--report " + first.string() + " is the input file"),
            std::string::npos)
      << derain.output;
  EXPECT_EQ(fs::readTextFile(first), firstBytes);

  // The log through a symlink to a plate frame: refused before a line is appended.
  stdfs::create_symlink(second, dir / "run.log");
  for (const std::string& log : {second.string(), (dir / "run.log").string()}) {
    const auto r = runPluvia({"render", plate, "-p", "moderate", "-o",
                              (dir / "o" / "r.####.png").string(), "--frames", "1", "--log", log});
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("refusing"), std::string::npos) << r.output;
    EXPECT_EQ(fs::readTextFile(second), secondBytes) << log;
  }

  // A text file that is an input (the preset) is refused as the log too.
  const stdfs::path preset =
      writeTextFile(dir, "p.json", R"({"pluvia": 1, "extends": "moderate"})");
  const std::string presetBytes = fs::readTextFile(preset);
  const auto p =
      runPluvia({"render", plate, "-p", preset.string(), "-o", (dir / "o2" / "r.####.png").string(),
                 "--frames", "1", "--log", preset.string()});
  EXPECT_NE(p.exitCode, 0) << p.output;
  EXPECT_EQ(fs::readTextFile(preset), presetBytes);
}
