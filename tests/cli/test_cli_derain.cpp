// `pluvia derain` end to end: on real panning rain footage (NTURain ra1) it writes a clean
// plate, mattes and a report whose angle says the rain falls near-vertically; bad input gets a
// clear error and loses nothing.
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_support.h"
#include "util/fs.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

std::string hashOfFile(const stdfs::path& path) {
  return fs::readTextFile(path);
}

}  // namespace

TEST(CliDerain, RealPanningFootageGivesCleanPlateMattesAndReport) {
  if (sharedData().empty()) GTEST_SKIP() << "../shared/data absent";
  const auto input = sharedData() / "rain_real/nturain_ra1_real_rain_panning/%05d.jpg";
  const auto dir = freshTempDir("cli_derain_real");
  const CommandResult r =
      runPluvia({"-q", "derain", input.string(), "-o", (dir / "clean.####.png").string(),
                 "--matte-out", (dir / "matte.####.png").string(), "--frames", "1-6", "--window",
                 "6", "--report", (dir / "report.json").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (int f = 1; f <= 6; ++f) {
    EXPECT_TRUE(stdfs::exists(dir / fmt::format("clean.{:04d}.png", f)));
    EXPECT_TRUE(stdfs::exists(dir / fmt::format("matte.{:04d}.png", f)));
  }
  const auto report = nlohmann::json::parse(fs::readTextFile(dir / "report.json"));
  // The rain in ra1 falls within a few degrees of vertical; the scene's rails are horizontal.
  EXPECT_LT(std::abs(report.at("angle_deg").get<double>()), 10.0) << report.dump(2);
  EXPECT_GT(report.at("windows").at(0).at("registration_shift_px").get<double>(), 1.0);  // it pans
  for (int c = 0; c < 3; ++c)
    EXPECT_GT(report.at("rain_color").at(c).get<double>(), 0.5);  // bright rain
  EXPECT_GE(report.at("iterations").get<int>(), 1);
  EXPECT_TRUE(std::isfinite(report.at("residual").get<double>()));
  // The matte is mostly empty and holds some rain.
  const Image matte = readImageFile(dir / "matte.0003.png");
  size_t lit = 0;
  for (size_t i = 0; i < matte.pixelCount(); ++i) lit += matte.rgba[i * 4] > 0.02f;
  EXPECT_GT(lit, matte.pixelCount() / 1000);
  EXPECT_LT(lit, matte.pixelCount() / 4);
}

// A blank frame (a flash, a lens cap) in panning footage is placed with a registered
// neighbour's motion, and the warning names it by the clip's own frame numbers.
TEST(CliDerain, AFrameTooBlankToRegisterIsNamedByItsClipFrameNumber) {
  if (sharedData().empty()) GTEST_SKIP() << "../shared/data absent";
  const auto real = sharedData() / "rain_real/nturain_ra1_real_rain_panning";
  const auto dir = freshTempDir("cli_derain_blank");
  for (int f = 101; f <= 106; ++f)
    writeImageFile(dir / fmt::format("rain.{:04d}.png", f),
                   f == 102 ? test::flatImage(640, 480, 0.5f, 0.5f, 0.5f)
                            : readImageFile(real / fmt::format("{:05d}.jpg", f - 100)));
  const CommandResult r = runPluvia({"derain", (dir / "rain.####.png").string(), "-o",
                                     (dir / "clean.####.png").string(), "--window", "6"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"frame 102 has too few features to register onto frame 104; "
                             "placed with frame 101's motion"});
}

TEST(CliDerain, FewerThanThreeFramesIsAClearErrorAndWritesNothing) {
  const auto dir = freshTempDir("cli_derain_two");
  for (int f : {1, 2})
    writeImageFile(dir / fmt::format("rain.{:04d}.png", f),
                   test::flatImage(32, 24, 0.4f, 0.4f, 0.4f));
  const CommandResult r = runPluvia(
      {"derain", (dir / "rain.####.png").string(), "-o", (dir / "clean.####.png").string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  expectOutputHas(r.output, {"at least 3 frames", "rain.####.png"});
  EXPECT_FALSE(stdfs::exists(dir / "clean.0001.png"));
}

// An EXR frame holding NaN and infinite pixels: they are replaced by 0 and named, frame and
// count, and neither reaches the clean plate (the solve's sums spread them over the window).
TEST(CliDerain, NonFinitePixelsAreNamedAndKeptOutOfTheCleanPlate) {
  const auto dir = freshTempDir("cli_derain_nan");
  for (int f : {1, 2, 3}) {
    Image frame = test::flatImage(48, 32, 0.3f, 0.35f, 0.4f);
    if (f == 2)
      for (int y = 10; y < 14; ++y)
        for (int x = 20; x < 24; ++x)
          for (int c = 0; c < 3; ++c)
            frame.rgba[(size_t(y) * 48 + x) * 4 + c] =
                y < 12 ? std::nanf("") : std::numeric_limits<float>::infinity();
    writeImageFile(dir / fmt::format("rain.{:04d}.exr", f), frame);
  }
  const CommandResult r = runPluvia({"derain", (dir / "rain.####.exr").string(), "-o",
                                     (dir / "clean.####.exr").string(), "--no-register"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"frame 2: 48 NaN/Inf values in", "rain.####.exr replaced by 0"});
  for (int f : {1, 2, 3}) {
    const Image clean = readImageFile(dir / fmt::format("clean.{:04d}.exr", f));
    for (float v : clean.rgba) ASSERT_TRUE(std::isfinite(v)) << "frame " << f;
  }
}

TEST(CliDerain, RefusesToOverwriteTheFootage) {
  const auto dir = freshTempDir("cli_derain_overwrite");
  for (int f : {1, 2, 3}) {
    const float grey = 0.2f + 0.1f * f;
    writeImageFile(dir / fmt::format("rain.{:04d}.png", f),
                   test::flatImage(32, 24, grey, grey, grey));
  }
  const std::string before = hashOfFile(dir / "rain.0002.png");
  const CommandResult r = runPluvia(
      {"derain", (dir / "rain.####.png").string(), "-o", (dir / "rain.%04d.png").string()});
  EXPECT_NE(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("refusing to overwrite"), std::string::npos) << r.output;
  EXPECT_EQ(hashOfFile(dir / "rain.0002.png"), before);
}

TEST(CliDerain, RenderCarriesStrokesCutFromTheGivenRainFootage) {
  if (sharedData().empty()) GTEST_SKIP() << "../shared/data absent";
  const auto rain = sharedData() / "rain_real/nturain_ra1_real_rain_panning/%05d.jpg";
  const auto dir = freshTempDir("cli_derain_render");
  const CommandResult r =
      runPluvia({"-q", "render", exampleClip().string(), "-p", "moderate", "-o",
                 (dir / "f.####.png").string(), "--frames", "5-5", "--set", "rain.strokes=derain",
                 "--set", "derain.input=" + rain.string(), "--set", "derain.frames=6", "--cache",
                 (dir / "cache").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_TRUE(stdfs::exists(dir / "f.0005.png"));
  // The strokes went to the cache, as an atlas of real (non-empty) mattes.
  int cached = 0;
  for (const auto& e : stdfs::directory_iterator(dir / "cache")) {
    if (e.path().filename().string().rfind("derain-", 0) != 0) continue;
    const auto atlas = nlohmann::json::parse(fs::readTextFile(e.path()));
    EXPECT_GE(atlas.at("rects").size(), 4u);
    ++cached;
  }
  EXPECT_EQ(cached, 1);
}
