// `pluvia plan`, `validate` and `describe`.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "test_support.h"

using namespace pluvia::test;

TEST(CliPlan, SaysWhatRunsAndWhatIsLeftOutAndWhy) {
  auto r = runPluvia({"plan", exampleClip().string(), "-p", "moderate", "--set", "fog.density=0",
                      "--set", "blur.sigma_px=0"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("skip    fog          no-op: density is 0"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("skip    blur         no-op: sigma_px is 0"), std::string::npos);
  EXPECT_NE(r.output.find("skip    derain       nothing reads its output (footage_strokes)"),
            std::string::npos);
  EXPECT_NE(r.output.find("run     rain"), std::string::npos);
  EXPECT_NE(r.output.find("48 frames"), std::string::npos);
  // Which sky lights the drops (the log gives its brightness once the plate is analysed).
  EXPECT_NE(r.output.find("drops lit by the plate and, above it, an overcast sky"),
            std::string::npos)
      << r.output;
}

TEST(CliPlan, CacheMakesLightingCachedOnTheSecondRun) {
  auto dir = freshTempDir("plan_cache");
  auto cache = (dir / "cache").string();
  auto first = runPluvia({"plan", exampleClip().string(), "-p", "drizzle", "--cache", cache});
  EXPECT_NE(first.output.find("run     lighting"), std::string::npos) << first.output;
  auto render = runPluvia({"render", exampleClip().string(), "-p", "drizzle", "--cache", cache,
                           "-o", (dir / "o.####.png").string(), "--frames", "0-0"});
  ASSERT_EQ(render.exitCode, 0) << render.output;
  auto second = runPluvia({"plan", exampleClip().string(), "-p", "drizzle", "--cache", cache});
  EXPECT_NE(second.output.find("cached  lighting"), std::string::npos) << second.output;
  auto other = runPluvia({"plan", exampleClip().string(), "-p", "drizzle", "--cache", cache,
                          "--set", "lighting.sample_frames=2"});
  EXPECT_NE(other.output.find("run     lighting"), std::string::npos) << other.output;
}

TEST(CliPlan, ResolvedPrintsTheFullPresetAsJson) {
  auto r = runPluvia(
      {"plan", exampleClip().string(), "-p", "storm", "--set", "rain.seed=9", "--resolved"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  auto json = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  EXPECT_EQ(json["rain"]["seed"], 9);
  EXPECT_EQ(json["rain"]["rate_mm_h"], 100);
  EXPECT_TRUE(json["fog"].contains("color_source"));  // defaults filled in
}

TEST(CliValidateDescribe, ValidateAndDescribe) {
  auto ok = runPluvia({"validate", "heavy"});
  EXPECT_EQ(ok.exitCode, 0) << ok.output;
  EXPECT_NE(ok.output.find("valid"), std::string::npos);
  auto bad =
      runPluvia({"validate", "heavy", "--set", "rain.wind.speed=3", "--set", "fog.color=red"});
  EXPECT_EQ(bad.exitCode, 2);  // --set mistakes are usage errors
  EXPECT_NE(bad.output.find("/rain/wind/speed: unknown key 'speed' (did you mean 'speed_m_s'?)"),
            std::string::npos)
      << bad.output;
  EXPECT_NE(bad.output.find("/fog/color: expected [r, g, b]"), std::string::npos) << bad.output;
  auto all = runPluvia({"describe"});
  EXPECT_EQ(all.exitCode, 0);
  for (const char* s :
       {"derain:", "lighting:", "depth:", "rain:", "darken:", "blur:", "fog:", "camera:", "color:"})
    EXPECT_NE(all.output.find(s), std::string::npos) << s;
  auto fog = runPluvia({"describe", "fog"});
  EXPECT_NE(fog.output.find("density"), std::string::npos);
  EXPECT_NE(fog.output.find("1/m"), std::string::npos);
  // With a preset, its own values where they differ from the built-in defaults: storm's rate and
  // wind, base's camera (the shipped camera, not the built-in 36 deg at f/11).
  auto storm = runPluvia({"describe", "-p", "storm"});
  ASSERT_EQ(storm.exitCode, 0) << storm.output;
  EXPECT_NE(storm.output.find("[storm: 100"), std::string::npos) << storm.output;
  EXPECT_NE(storm.output.find("[storm: 12"), std::string::npos) << storm.output;
  auto camera = runPluvia({"describe", "camera", "-p", "base"});
  EXPECT_NE(camera.output.find("[base: 50"), std::string::npos) << camera.output;
  EXPECT_NE(camera.output.find("[base: 4]"), std::string::npos) << camera.output;  // f/4
  EXPECT_EQ(fog.output.find("[base"), std::string::npos);  // none without -p
  auto unknown = runPluvia({"describe", "rian"});
  EXPECT_EQ(unknown.exitCode, 2);
  EXPECT_NE(unknown.output.find("did you mean 'rain'?"), std::string::npos);
  auto help = runPluvia({"--help"});
  EXPECT_NE(help.output.find("Exit codes"), std::string::npos);
}

TEST(CliPlan, PresetHelpListsEveryShippedPreset) {
  const auto help = runPluvia({"render", "--help"});
  ASSERT_EQ(help.exitCode, 0) << help.output;
  EXPECT_NE(help.output.find("drizzle, gentle, hard, heavy, moderate, storm"), std::string::npos)
      << help.output;
}
