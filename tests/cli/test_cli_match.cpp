// `pluvia match` on pluvia's own rain of known settings: the example plate (768 px wide) rained at
// 12 mm/h with a 1/400 s shutter and 2 m/s of wind to the right (darken, blur and fog off, as the
// match compares streaks alone), drawn as deep as that camera sees it (rain.far_m 0: 2.48 m), then
// matched from `moderate` (8 mm/h, 2.28 m, no wind across) filmed at 1/600 s. The rate, the
// shutter, the depth and the streaks' angle are recovered (measured: 12.3 mm/h, 1/486 s, the rain
// seen to 1.96 m of the 2.48 drawn; the shutter comes out short because the walkers' outlines leave
// bright residue in the reference's clean plates, which reads as brighter streaks). Rain drawn
// deeper than the camera's own rule is matched as deeper rain. The preset written extends the base
// and resolves. Bad input loses nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <regex>
#include <string>

#include <nlohmann/json.hpp>

#include "test_support.h"
#include "util/fs.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

// The number after `label` in the output (the reference's angle: "angle -22.9 deg").
double numberAfter(const std::string& output, const std::string& label) {
  const std::regex pattern(label + " ([-+0-9.]+)");
  std::smatch found;
  if (!std::regex_search(output, found, pattern)) return NAN;
  return std::stod(found[1]);
}

// The example's first 8 frames at `proxy` of their size rained with `rain` (a preset's "rain"
// and "camera" members, JSON) with wet ground, darken, blur and fog off, then matched from
// `moderate` at a stated 1/600 s over `steps` renders at `widthPx`: the match's output; the preset
// it wrote is `dir`/matched.json. (From `moderate` alone the search would start at the reference's
// own shutter, here the walkers' motion blur's upper bound of 1/500 s, and a rate, a shutter and a
// depth trade against each other: from there 8 steps end at 17.5 mm/h and 1/601 s, x1.07.)
CommandResult matchKnownRain(const stdfs::path& dir, const std::string& rainAndCamera,
                             const std::string& steps, const std::string& proxy = "0.3334",
                             const std::string& widthPx = "256") {
  const stdfs::path truth =
      writeTextFile(dir, "truth.json",
                    R"({"pluvia": 1, "extends": "moderate", )" + rainAndCamera +
                        R"(, "wet_ground": {"enabled": false}, "darken": {"enabled": false}, )"
                        R"("blur": {"enabled": false}, "fog": {"enabled": false}})");
  const CommandResult rendered =
      runPluvia({"render", exampleClip().string(), "-p", truth.string(), "--frames", "0-7",
                 "--proxy", proxy, "-o", (dir / "rain.####.png").string(), "-q"});
  EXPECT_EQ(rendered.exitCode, 0) << rendered.output;
  const stdfs::path start =
      writeTextFile(dir, "start.json",
                    R"({"pluvia": 1, "extends": "moderate", "camera": {"exposure_s": 0.0016667}})");
  return runPluvia({"match", (dir / "rain.####.png").string(), "-o",
                    (dir / "matched.json").string(), "-p", start.string(), "--width", widthPx,
                    "--frames", "8", "--steps", steps});
}

}  // namespace

// Known rain (12 mm/h, 1/400 s, drawn to the camera's 2.48 m) matched from 8 mm/h at 1/600 s. The
// rate, the shutter and the depth trade against each other, and the reference's layer carries
// the estimator's residue (the walkers' outlines): the truth's own settings score x1.21 on the
// match's measure, the match x1.09 at 16.9 mm/h, 1/536 s and 1.51 m (before 8-bit movies were
// read at their own codes, 12.7 mm/h, 1/491 s, 1.92 m: the same valley, another point of it). So
// the match must fit the statistics at least as well as the truth does, each setting within a
// factor 2 of the truth's (a search that traded the opacity against the rate matched 12 mm/h as
// 0.8), and the angle within 2 degrees.
TEST(CliMatch, FitsKnownRainAsWellAsItsOwnSettingsAndFindsItsAngle) {
  const auto dir = freshTempDir("match");
  const stdfs::path preset = dir / "matched.json";
  const CommandResult r =
      matchKnownRain(dir,
                     R"("rain": {"rate_mm_h": 12, "wind": {"speed_m_s": 2, "dir_deg": 0}}, )"
                     R"("camera": {"exposure_s": 0.0025})",
                     "8", "1");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json matched = nlohmann::json::parse(fs::readTextFile(preset));
  EXPECT_EQ(matched["extends"], (dir / "start.json").string());
  const double rate = matched["rain"]["rate_mm_h"];
  EXPECT_GT(rate, 12.0 / 2.0) << r.output;
  EXPECT_LT(rate, 12.0 * 2.0) << r.output;
  const double exposure = matched["camera"]["exposure_s"];
  EXPECT_GT(exposure, 0.0025 / 2.0) << r.output;
  EXPECT_LT(exposure, 0.0025 * 2.0) << r.output;
  // 2 x the focal length (823 px) x the median drop at 12 mm/h (1.51 mm): rain/rain_depth.h.
  const double farMeters = matched["rain"]["far_m"];
  EXPECT_GT(farMeters, 2.48 / 2.0) << r.output;
  EXPECT_LT(farMeters, 2.48 * 2.0) << r.output;
  const stdfs::path truthSettings = writeTextFile(
      dir, "truth_settings.json",
      R"({"pluvia": 1, "extends": "moderate", "rain": {"rate_mm_h": 12, "far_m": 2.48, )"
      R"("wind": {"speed_m_s": 2, "dir_deg": 0}}, "camera": {"exposure_s": 0.0025}})");
  const CommandResult truth =
      runPluvia({"match", (dir / "rain.####.png").string(), "-o", (dir / "truth.out.json").string(),
                 "-p", truthSettings.string(), "--width", "256", "--frames", "8", "--steps", "1"});
  ASSERT_EQ(truth.exitCode, 0) << truth.output;
  const auto typical = [](const std::string& output) {
    std::smatch found;
    return std::regex_search(output, found, std::regex("\nmatch: typical x([0-9.]+)"))
               ? std::stod(found[1])
               : NAN;
  };
  EXPECT_LE(typical(r.output), typical(truth.output)) << r.output << truth.output;
  // The wind blows to the camera's right, and the match's streaks lean as the reference's do.
  EXPECT_EQ(matched["rain"]["wind"]["dir_deg"], 0) << r.output;
  const double referenceAngle = numberAfter(r.output, "angle");
  std::smatch best;
  ASSERT_TRUE(std::regex_search(r.output, best, std::regex("([-+0-9.]+)  <- the match")))
      << r.output;
  EXPECT_NEAR(std::stod(best[1]), referenceAngle, 2.0) << r.output;
  EXPECT_LT(referenceAngle, -10.0) << r.output;
  // What was written renders: a plan with it resolves.
  const CommandResult plan = runPluvia({"plan", exampleClip().string(), "-p", preset.string()});
  EXPECT_EQ(plan.exitCode, 0) << plan.output;
}

TEST(CliMatch, FindsHowDeepTheRainIsSeen) {
  // Rain drawn to 6 m, deeper than the camera's own rule (a sharper camera, or bigger drops than
  // the rate's), measured at 640 px: the match, starting from the base's 2.28 m, finds the deeper
  // rain (measured: 4.6 m at 10.6 mm/h and 1/353 s, typical x1.05) instead of keeping the depth and
  // raising the rate.
  const auto dir = freshTempDir("match_deep");
  const CommandResult r = matchKnownRain(
      dir, R"("rain": {"rate_mm_h": 12, "far_m": 6}, "camera": {"exposure_s": 0.0025})", "4", "1",
      "640");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const nlohmann::json matched = nlohmann::json::parse(fs::readTextFile(dir / "matched.json"));
  const double farMeters = matched["rain"]["far_m"];
  EXPECT_GE(farMeters, 4.0) << r.output;
  EXPECT_LE(farMeters, 9.0) << r.output;
  const double rate = matched["rain"]["rate_mm_h"];
  EXPECT_NEAR(rate, 12.0, 0.35 * 12.0) << r.output;
  std::smatch typical;
  ASSERT_TRUE(std::regex_search(r.output, typical, std::regex("\nmatch: typical x([0-9.]+)")))
      << r.output;
  EXPECT_LT(std::stod(typical[1]), 1.15) << r.output;
}

TEST(CliMatch, RainWithoutAClearDirectionKeepsTheBasesWind) {
  // Each drop blown its own way (10 m/s of spread): the streaks' angles spread about 60 deg, so
  // there is no angle to match, and the preset written keeps the base's wind.
  const auto dir = freshTempDir("match_wild");
  const stdfs::path preset = dir / "matched.json";
  const CommandResult r =
      matchKnownRain(dir, R"("rain": {"rate_mm_h": 12, "spread_m_s": 10})", "2");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output, {"not matched, the base's wind kept"});
  const nlohmann::json matched = nlohmann::json::parse(fs::readTextFile(preset));
  EXPECT_FALSE(matched["rain"].contains("wind")) << matched.dump(2);
  EXPECT_TRUE(matched["rain"].contains("rate_mm_h"));
}

TEST(CliMatch, ABaseOrAReferenceIsNeverWrittenOver) {
  const auto dir = freshTempDir("match_refuse");
  const stdfs::path base = writeTextFile(dir, "base.json", R"({"pluvia": 1, "extends": "gentle"})");
  const std::string before = fs::readTextFile(base);
  const CommandResult overBase = runPluvia(
      {"match", exampleClip().string(), "-o", base.string(), "-p", base.string(), "--steps", "1"});
  EXPECT_EQ(overBase.exitCode, 2) << overBase.output;
  expectOutputHas(overBase.output, {"base.json"});
  EXPECT_EQ(fs::readTextFile(base), before);
  const CommandResult missing =
      runPluvia({"match", (dir / "no_such_rain.mp4").string(), "-o", (dir / "out.json").string()});
  EXPECT_EQ(missing.exitCode, 1) << missing.output;
  expectOutputHas(missing.output, {"no_such_rain.mp4"});
  EXPECT_FALSE(stdfs::exists(dir / "out.json"));
}
