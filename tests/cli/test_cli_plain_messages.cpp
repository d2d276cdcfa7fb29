// Odd inputs that gave a library's raw message, or failed where there was work to do (issue 59's
// adversarial pass): frames too small for optical flow, a rain rate whose flux underflows, names
// too long for the file system, a plot that is no PNG, and cache entries edited out of shape.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

// OpenCV's DIS flow asserts on frames under 12 px on both sides: the render said "OpenCV(4.6.0)
// ... dis_flow.cpp:1450: error: (-201...)". The plate's motion is not followed there, and the log
// says why.
TEST(CliPlainMessages, FramesTooSmallForOpticalFlowRender) {
  const stdfs::path dir = freshTempDir("plain_tiny");
  const std::string plate = writeTexturedPlate(dir, 1, 4, 10, 8);
  const auto r =
      runPluvia({"render", plate, "-p", "moderate", "-o", (dir / "o.####.png").string()});
  EXPECT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"frames of 10x8 px are too small to follow their motion"});
  EXPECT_EQ(r.output.find("OpenCV"), std::string::npos) << r.output;
  EXPECT_TRUE(stdfs::exists(dir / "o.0004.png"));
}

// 1e-308 mm/h: the impact flux underflows to 0 and the splash stage threw "ImpactDiameters: no
// drop lands". No drop lands: the frame is the plate's.
TEST(CliPlainMessages, ARateWhoseFluxUnderflowsLandsNoDrop) {
  const stdfs::path dir = freshTempDir("plain_tiny_rate");
  const std::string plate = writeTexturedPlate(dir, 1, 1, 64, 48);
  const auto r = runPluvia({"render", plate, "-p", "moderate", "--set", "rain.rate_mm_h=1e-308",
                            "--set", "ripples.enabled=true", "-o", (dir / "o.####.png").string()});
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(stdfs::exists(dir / "o.0001.png"));
}

// A name longer than the file system's 255 bytes: "filesystem error: status: File name too long"
// for a preset, "input not found" for a plate that may well exist under a shorter name.
TEST(CliPlainMessages, NamesTooLongSayWhatIsWrongWithThem) {
  const stdfs::path dir = freshTempDir("plain_long");
  const std::string plate = writeTexturedPlate(dir, 1, 1);
  const std::string longName(300, 'a');
  auto r = runPluvia({"render", plate, "-p", longName, "-o", (dir / "o.####.png").string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  expectOutputHas(r.output, {"no preset file or shipped preset named 'aaa"});
  EXPECT_EQ(r.output.find("filesystem error"), std::string::npos) << r.output;
  r = runPluvia({"render", (dir / (longName + ".png")).string(), "-p", "moderate", "-o",
                 (dir / "o.####.png").string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  expectOutputHas(r.output, {"cannot read the input", "File name too long"});
  EXPECT_FALSE(stdfs::exists(dir / "o.0001.png"));
}

// `report optics --plot x.txt` ran for 17 s and then failed to write the plot.
TEST(CliPlainMessages, APlotThatIsNoPngIsRefusedBeforeAnyWork) {
  const auto r = runPluviaTimed({"report", "optics", "--plot", "x.txt"});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  expectOutputHas(r.output, {"--plot: the plot is a PNG: give PLOT.png, not x.txt"});
}

// Cache entries edited out of shape: a still-motion entry without its number failed the render
// with nlohmann's "[json.exception.type_error.302]"; a still of another size was taken and drew
// from a 2x2 picture. Each is made again, with a warning, and the frame is the one a fresh
// cache gives.
TEST(CliPlainMessages, MalformedCacheEntriesAreMadeAgain) {
  const stdfs::path dir = freshTempDir("plain_cache");
  const std::string plate = writeTexturedPlate(dir, 1, 4, 96, 64);
  const stdfs::path cache = dir / "cache";
  const auto render = [&](const std::string& output) {
    return runPluvia({"render", plate, "-p", "moderate", "--frames", "2-2", "--cache",
                      cache.string(), "-o", (dir / output).string()});
  };
  auto r = render("fresh.####.png");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  std::vector<stdfs::path> motion, stills;
  for (const auto& entry : stdfs::directory_iterator(cache)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("still-motion-")) motion.push_back(entry.path());
    if (name.starts_with("still-") && !name.starts_with("still-motion-") &&
        entry.path().extension() == ".json")
      stills.push_back(entry.path());
  }
  ASSERT_EQ(motion.size(), 1u);
  ASSERT_EQ(stills.size(), 1u);
  std::ofstream(motion[0]) << R"({"mismatch": "x"})";
  {
    std::ofstream(stills[0]) << R"({"bytes": 64, "header": {"width": 2, "height": 2}})";
    stdfs::path blob = stills[0];
    blob.replace_extension(".bin");
    stdfs::resize_file(blob, 64);
  }
  r = render("again.####.png");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"no \"mismatch\" number", "not a still of the frames' 96x64 px"});
  EXPECT_EQ(readImageFile(dir / "again.0002.png").rgba, readImageFile(dir / "fresh.0002.png").rgba);
}
