#include <gtest/gtest.h>

#include <fstream>

#include "preset/preset.h"
#include "stages/registry.h"
#include "test_support.h"

using namespace pluvia;

namespace {
std::filesystem::path writePreset(const std::filesystem::path& dir, const std::string& name, const std::string& text) {
  auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

std::vector<std::string> problemsOf(const std::string& preset, const std::vector<std::string>& sets = {}) {
  try {
    Preset::resolve(preset, sets, presetSchema());
  } catch (const PresetError& e) {
    return e.problems();
  }
  return {};
}

bool anyContains(const std::vector<std::string>& lines, const std::string& needle) {
  for (const auto& l : lines)
    if (l.find(needle) != std::string::npos) return true;
  return false;
}
}  // namespace

TEST(Preset, EveryShippedPresetIsValid) {
  auto names = shippedPresetNames();
  for (const char* required : {"drizzle", "moderate", "heavy", "storm"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), required), names.end()) << required;
  }
  for (const auto& name : names) EXPECT_TRUE(problemsOf(name).empty()) << name;
  EXPECT_TRUE(problemsOf((test::sourceDir() / "examples/street/street.json").string()).empty());
}

TEST(Preset, ExtendsMergesAndOverridesApply) {
  auto dir = test::freshTempDir("preset_extends");
  auto path = writePreset(dir, "mine.json", R"({"pluvia": 1, "extends": "heavy", "fog": {"density": 0.5}})");
  Preset p = Preset::resolve(path.string(), {"rain.seed=3", "blur.sigma_px=2.5"}, presetSchema());
  EXPECT_DOUBLE_EQ(p.number("fog.density"), 0.5);      // own value wins
  EXPECT_DOUBLE_EQ(p.number("rain.rate_mm_h"), 40.0);  // from heavy
  EXPECT_DOUBLE_EQ(p.number("rain.seed"), 3.0);        // --set
  EXPECT_DOUBLE_EQ(p.number("blur.sigma_px"), 2.5);
  EXPECT_DOUBLE_EQ(p.number("camera.fov_deg"), 36.0);  // from base
  EXPECT_EQ(p.string("fog.color_source"), "environment");  // default filled
  EXPECT_FALSE(p.has("extends"));
}

TEST(Preset, ReportsEveryProblemAtOnceWithPathsAndSuggestions) {
  auto dir = test::freshTempDir("preset_problems");
  auto path = writePreset(dir, "bad.json", R"({
    "pluvia": 1,
    "rain": {"rate_mm_hr": 10, "seed": "seven", "wind": {"speed_m_s": -3}},
    "fogg": {},
    "fog": {"density": 20, "color_source": "enviroment"},
    "depth": {"layers": [{"type": "card", "distanse_m": 4}, {"type": "wall"}]}
  })");
  auto problems = problemsOf(path.string(), {"blur.sigma=2"});
  EXPECT_TRUE(anyContains(problems, "/rain/rate_mm_hr: unknown key 'rate_mm_hr' (did you mean 'rate_mm_h'?)"));
  EXPECT_TRUE(anyContains(problems, "/rain/seed: expected an integer"));
  EXPECT_TRUE(anyContains(problems, "/rain/wind/speed_m_s: must be between 0 and 60 m/s (got -3)"));
  EXPECT_TRUE(anyContains(problems, "/fogg: unknown section 'fogg' (did you mean 'fog'?)"));
  EXPECT_TRUE(anyContains(problems, "/fog/density: must be between 0 and 10"));
  EXPECT_TRUE(anyContains(problems, "(did you mean 'environment'?)"));
  EXPECT_TRUE(anyContains(problems, "/depth/layers/0/distanse_m: unknown key"));
  EXPECT_TRUE(anyContains(problems, "/depth/layers/1/type: unknown item type"));
  EXPECT_TRUE(anyContains(problems, "/blur/sigma: unknown key 'sigma' (did you mean 'sigma_px'?)"));
  EXPECT_GE(problems.size(), 9u);
}

TEST(Preset, SchemaVersionCycleAndMissingPresetAreErrors) {
  auto dir = test::freshTempDir("preset_cycle");
  writePreset(dir, "a.json", R"({"pluvia": 1, "extends": "b.json"})");
  writePreset(dir, "b.json", R"({"pluvia": 1, "extends": "a.json"})");
  EXPECT_TRUE(anyContains(problemsOf((dir / "a.json").string()), "cycle"));
  writePreset(dir, "v2.json", R"({"pluvia": 2})");
  EXPECT_TRUE(anyContains(problemsOf((dir / "v2.json").string()), "schema version 2 is not supported"));
  writePreset(dir, "broken.json", R"({"pluvia": 1, )");
  EXPECT_TRUE(anyContains(problemsOf((dir / "broken.json").string()), "not valid JSON"));
  EXPECT_TRUE(anyContains(problemsOf("moderat"), "did you mean 'moderate'?"));
}

TEST(Preset, OverrideParsesJsonValuesAndIndexesLists) {
  nlohmann::json doc = nlohmann::json::parse(R"({"depth": {"layers": [{"type": "card", "distance_m": 3}]}})");
  applyOverride(doc, "depth.layers.0.distance_m=12.5");
  applyOverride(doc, "fog.color=[0.1,0.2,0.3]");
  applyOverride(doc, "rain.strokes=my library.json");
  EXPECT_DOUBLE_EQ(doc["depth"]["layers"][0]["distance_m"].get<double>(), 12.5);
  EXPECT_EQ(doc["fog"]["color"].size(), 3u);
  EXPECT_EQ(doc["rain"]["strokes"], "my library.json");
  EXPECT_THROW(applyOverride(doc, "no_equals_sign"), PresetError);
  EXPECT_THROW(applyOverride(doc, "depth.layers.5.distance_m=1"), PresetError);
}

TEST(Preset, HashChangesWithAnyValue) {
  Preset a = Preset::resolve("moderate", {}, presetSchema());
  Preset b = Preset::resolve("moderate", {"rain.seed=2"}, presetSchema());
  Preset c = Preset::resolve("moderate", {}, presetSchema());
  EXPECT_NE(a.hash(), b.hash());
  EXPECT_EQ(a.hash(), c.hash());
}
