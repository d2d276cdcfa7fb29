#include <gtest/gtest.h>

#include <fstream>
#include <iostream>

#include "geometry/camera.h"
#include "pipeline/camera_settings.h"
#include "preset/preset.h"
#include "preset/ramp.h"
#include "rain/rain_types.h"
#include "stages/registry.h"
#include "test_support.h"

using namespace pluvia;

namespace {

std::vector<std::string> problemsOf(const std::string& preset,
                                    const std::vector<std::string>& sets = {}) {
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

// Expects each of `needles` in some line of `problems`.
void expectProblems(const std::vector<std::string>& problems,
                    const std::vector<std::string>& needles) {
  for (const auto& needle : needles) EXPECT_TRUE(anyContains(problems, needle)) << needle;
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

// Mizukami et al.'s Table 1 rain types ship as presets of the same name at the table's rate.
TEST(Preset, RainTypesShipAtTheirTableRate) {
  for (const std::string& name : rain::rainTypeNames()) {
    const Preset p = Preset::resolve(name, {}, presetSchema());
    EXPECT_DOUBLE_EQ(p.number("rain.rate_mm_h"), rain::findRainType(name)->rateMmH) << name;
  }
}

TEST(Preset, ExtendsMergesAndOverridesApply) {
  auto dir = test::freshTempDir("preset_extends");
  auto path = test::writeTextFile(dir, "mine.json",
                                  R"({"pluvia": 1, "extends": "heavy", "fog": {"density": 0.5}})");
  Preset p = Preset::resolve(path.string(), {"rain.seed=3", "blur.sigma_px=2.5"}, presetSchema());
  EXPECT_DOUBLE_EQ(p.number("fog.density"), 0.5);      // own value wins
  EXPECT_DOUBLE_EQ(p.number("rain.rate_mm_h"), 40.0);  // from heavy
  EXPECT_DOUBLE_EQ(p.number("rain.seed"), 3.0);        // --set
  EXPECT_DOUBLE_EQ(p.number("blur.sigma_px"), 2.5);
  EXPECT_DOUBLE_EQ(p.number("camera.fov_deg"), 50.0);  // from base
  EXPECT_EQ(p.string("fog.color_source"), "horizon");  // default filled
  EXPECT_FALSE(p.has("extends"));
}

TEST(Preset, ReportsEveryProblemAtOnceWithPathsAndSuggestions) {
  auto dir = test::freshTempDir("preset_problems");
  auto path = test::writeTextFile(dir, "bad.json", R"({
    "pluvia": 1,
    "rain": {"rate_mm_hr": 10, "seed": "seven", "wind": {"speed_m_s": -3}},
    "fogg": {},
    "fog": {"density": 20, "color_source": "horizn"},
    "depth": {"layers": [{"type": "card", "distanse_m": 4}, {"type": "wall"}]}
  })");
  auto problems = problemsOf(path.string(), {"blur.sigma=2"});
  expectProblems(
      problems,
      {"/rain/rate_mm_hr: unknown key 'rate_mm_hr' (did you mean 'rate_mm_h'?)",
       "/rain/seed: expected an integer",
       "/rain/wind/speed_m_s: must be between 0 and 60 m/s (got -3)",
       "/fogg: unknown section 'fogg' (did you mean 'fog'?)",
       "/fog/density: must be between 0 and 10", "(did you mean 'horizon'?)",
       "/depth/layers/0/distanse_m: unknown key", "/depth/layers/1/type: unknown item type",
       "/blur/sigma: unknown key 'sigma' (did you mean 'sigma_px'?)"});
  EXPECT_GE(problems.size(), 9u);
}

TEST(Preset, SchemaVersionCycleAndMissingPresetAreErrors) {
  auto dir = test::freshTempDir("preset_cycle");
  test::writeTextFile(dir, "a.json", R"({"pluvia": 1, "extends": "b.json"})");
  test::writeTextFile(dir, "b.json", R"({"pluvia": 1, "extends": "a.json"})");
  EXPECT_TRUE(anyContains(problemsOf((dir / "a.json").string()), "cycle"));
  test::writeTextFile(dir, "v2.json", R"({"pluvia": 2})");
  EXPECT_TRUE(
      anyContains(problemsOf((dir / "v2.json").string()), "schema version 2 is not supported"));
  test::writeTextFile(dir, "broken.json", R"({"pluvia": 1, )");
  EXPECT_TRUE(anyContains(problemsOf((dir / "broken.json").string()), "not valid JSON"));
  EXPECT_TRUE(anyContains(problemsOf("moderat"), "did you mean 'moderate'?"));
}

TEST(Preset, OverrideParsesJsonValuesAndIndexesLists) {
  nlohmann::json doc =
      nlohmann::json::parse(R"({"depth": {"layers": [{"type": "card", "distance_m": 3}]}})");
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

TEST(Ramp, InterpolatesHoldsAndSmooths) {
  Ramp linear({{0, 0}, {48, 40}, {96, 10}});
  EXPECT_DOUBLE_EQ(linear.valueAt(-5), 0.0);  // before the first key: the first value
  EXPECT_DOUBLE_EQ(linear.valueAt(0), 0.0);
  EXPECT_DOUBLE_EQ(linear.valueAt(12), 10.0);
  EXPECT_DOUBLE_EQ(linear.valueAt(24.5), 40.0 * 24.5 / 48.0);  // fractional frames
  EXPECT_DOUBLE_EQ(linear.valueAt(48), 40.0);
  EXPECT_DOUBLE_EQ(linear.valueAt(72), 25.0);
  EXPECT_DOUBLE_EQ(linear.valueAt(96), 10.0);
  EXPECT_DOUBLE_EQ(linear.valueAt(1000), 10.0);  // after the last key: the last value
  EXPECT_TRUE(linear.animated());

  Ramp smooth({{0, 0}, {48, 40}}, RampInterpolation::Smooth);
  EXPECT_DOUBLE_EQ(smooth.valueAt(0), 0.0);
  EXPECT_DOUBLE_EQ(smooth.valueAt(24), 20.0);  // smoothstep is symmetric about the middle
  EXPECT_DOUBLE_EQ(smooth.valueAt(12), 40.0 * (0.25 * 0.25 * (3 - 2 * 0.25)));
  EXPECT_LT(smooth.valueAt(6), linear.valueAt(6));  // eases in
  EXPECT_DOUBLE_EQ(smooth.valueAt(48), 40.0);

  Ramp hold({{10, 1}, {20, 5}, {30, 2}}, RampInterpolation::Hold);
  EXPECT_DOUBLE_EQ(hold.valueAt(0), 1.0);
  EXPECT_DOUBLE_EQ(hold.valueAt(19.99), 1.0);
  EXPECT_DOUBLE_EQ(hold.valueAt(20), 5.0);
  EXPECT_DOUBLE_EQ(hold.valueAt(29), 5.0);
  EXPECT_DOUBLE_EQ(hold.valueAt(31), 2.0);

  EXPECT_FALSE(Ramp(3.0).animated());
  EXPECT_DOUBLE_EQ(Ramp(3.0).valueAt(100), 3.0);
  EXPECT_FALSE(Ramp({{0, 2}, {10, 2}}).animated());
  EXPECT_THROW(Ramp({{10, 0}, {5, 1}}), Error);
  EXPECT_THROW(Ramp(std::vector<RampKey>{}), Error);
}

// The names a preset gives: each parses to the interpolation that is named by it, "linear" (the
// default) first; any other word is refused.
TEST(Ramp, InterpolationNamesParseAndNameAlike) {
  EXPECT_EQ(rampInterpolationNames(), (std::vector<std::string>{"linear", "smooth", "hold"}));
  for (const std::string& name : rampInterpolationNames()) {
    RampInterpolation parsed = RampInterpolation::Linear;
    ASSERT_TRUE(parseRampInterpolation(name, parsed)) << name;
    EXPECT_EQ(rampInterpolationName(parsed), name);
  }
  RampInterpolation untouched = RampInterpolation::Hold;
  EXPECT_FALSE(parseRampInterpolation("cubic", untouched));
  EXPECT_EQ(untouched, RampInterpolation::Hold);
  EXPECT_STREQ(rampInterpolationName(RampInterpolation::Smooth), "smooth");
}

TEST(Preset, NumbersAcceptKeyframes) {
  auto dir = test::freshTempDir("preset_keys");
  auto path = test::writeTextFile(dir, "ramp.json", R"({"pluvia": 1, "extends": "moderate",
    "rain": {"rate_mm_h": {"keys": [[0, 0], [48, 40]], "interpolation": "linear"},
             "wind": {"speed_m_s": {"keys": [[10, 2], [20, 8]], "interpolation": "hold"},
                      "dir_deg": {"keys": [[0, 0], [100, 90]], "interpolation": "smooth"}}},
    "camera": {"exposure_s": {"keys": [[0, 0.01]]}}})");
  Preset p = Preset::resolve(path.string(), {}, presetSchema());
  EXPECT_TRUE(p.ramp("rain.rate_mm_h").animated());
  EXPECT_DOUBLE_EQ(p.number("rain.rate_mm_h"), 0.0);  // the first key's value
  EXPECT_DOUBLE_EQ(p.number("rain.rate_mm_h", -10), 0.0);
  EXPECT_DOUBLE_EQ(p.number("rain.rate_mm_h", 24), 20.0);
  EXPECT_DOUBLE_EQ(p.number("rain.rate_mm_h", 48), 40.0);
  EXPECT_DOUBLE_EQ(p.number("rain.rate_mm_h", 1e6), 40.0);
  EXPECT_DOUBLE_EQ(p.number("rain.wind.speed_m_s", 15), 2.0);
  EXPECT_DOUBLE_EQ(p.number("rain.wind.speed_m_s", 20), 8.0);
  EXPECT_DOUBLE_EQ(p.number("rain.wind.dir_deg", 50), 45.0);
  EXPECT_LT(p.number("rain.wind.dir_deg", 25), 22.5);
  EXPECT_FALSE(p.ramp("camera.exposure_s").animated());  // one key: constant
  EXPECT_DOUBLE_EQ(p.number("camera.exposure_s", 99), 0.01);
  // Plain numbers are the same at every frame.
  EXPECT_FALSE(p.ramp("camera.fov_deg").animated());
  EXPECT_DOUBLE_EQ(p.number("camera.fov_deg", 17), p.number("camera.fov_deg"));
  // Interpolation defaults to linear and is written out in the resolved JSON.
  Preset q = Preset::resolve("moderate", {"rain.rate_mm_h={\"keys\": [[0, 0], [10, 10]]}"},
                             presetSchema());
  EXPECT_EQ(q.at("rain.rate_mm_h")["interpolation"], "linear");
  EXPECT_DOUBLE_EQ(q.number("rain.rate_mm_h", 5), 5.0);
}

TEST(Preset, SetAcceptsKeyShorthandAndConstants) {
  Preset p = Preset::resolve(
      "moderate", {"rain.rate_mm_h=[[0,0],[48,40]]", "rain.wind.speed_m_s=25"}, presetSchema());
  EXPECT_TRUE(p.ramp("rain.rate_mm_h").animated());
  EXPECT_DOUBLE_EQ(p.number("rain.rate_mm_h", 12), 10.0);
  EXPECT_EQ(p.at("rain.rate_mm_h"),
            nlohmann::json::parse(R"({"keys": [[0, 0], [48, 40]], "interpolation": "linear"})"));
  EXPECT_FALSE(p.ramp("rain.wind.speed_m_s").animated());
  EXPECT_DOUBLE_EQ(p.number("rain.wind.speed_m_s"), 25.0);
  EXPECT_DOUBLE_EQ(p.number("rain.wind.speed_m_s", 30), 25.0);
  // Keys can be edited one by one once they exist.
  Preset q = Preset::resolve("moderate",
                             {"rain.rate_mm_h=[[0,0],[48,40]]", "rain.rate_mm_h.keys.1.1=20",
                              "rain.rate_mm_h.interpolation=hold"},
                             presetSchema());
  EXPECT_DOUBLE_EQ(q.number("rain.rate_mm_h", 47), 0.0);
  EXPECT_DOUBLE_EQ(q.number("rain.rate_mm_h", 48), 20.0);
}

TEST(Preset, KeyframeProblemsNameTheirPaths) {
  auto dir = test::freshTempDir("preset_bad_keys");
  auto path = test::writeTextFile(dir, "bad.json", R"({"pluvia": 1,
    "rain": {"rate_mm_h": {"keys": [[0, 0], [48, 4000], [40, 1]], "interpolation": "cubic"},
             "seed": {"keys": [[0, 1], [10, 2.5]]},
             "wind": {"speed_m_s": {"keys": []}, "dir_deg": {"key": [[0, 1]]}}},
    "camera": {"exposure_s": {"keys": [[0, 0.01], [0, 0.02], ["a", 0.01], [5]]}},
    "fog": {"density": "thick"}})");
  auto problems = problemsOf(path.string(), {"blur.sigma_px=[[0,1],[0,2]]"});
  for (const auto& line : problems) std::cerr << line << "\n";
  expectProblems(problems,
                 {"/rain/rate_mm_h/keys/1/1: must be between 0 and",
                  "/rain/rate_mm_h/keys/2/0: key frames must increase strictly",
                  "/rain/rate_mm_h/interpolation: expected one of: linear, smooth, hold"});
  // Values the shot fixes once (the seed, a blur radius) say so rather than take keys.
  expectProblems(problems,
                 {"/rain/seed: cannot be keyframed, it is fixed over the shot",
                  "/rain/wind/speed_m_s/keys: expected a list of at least one [frame, value] key",
                  "/rain/wind/dir_deg/key: unknown key 'key' in keyframes (did you mean 'keys'?)",
                  "/rain/wind/dir_deg/keys: missing"});
  expectProblems(problems, {"/camera/exposure_s/keys/1/0: key frames must increase strictly",
                            "/camera/exposure_s/keys/2/0: expected a frame number",
                            "/camera/exposure_s/keys/3: expected [frame, value]",
                            "/blur/sigma_px: cannot be keyframed",  // --set shorthand
                            "/fog/density: expected a number"});
  // List item fields not marked keyframable take plain numbers only.
  auto items = problemsOf(
      "moderate",
      {R"(camera.path=[{"frame": 0, "position_m": [0, 1, 0], "yaw_deg": [[0, 1], [10, 2]]}])"});
  EXPECT_TRUE(anyContains(items, "/camera/path/0/yaw_deg: expected a number"));
}

TEST(Preset, DepthLayerFieldsAcceptKeyframesAndPolygons) {
  Preset p = Preset::resolve("moderate", {R"(depth.layers=[{"type": "ground"},
          {"type": "card", "distance_m": [[0, 10], [20, 30]], "y1": {"keys": [[0, 0.2], [5, 0.3]], "interpolation": "hold"}},
          {"type": "polygon", "points": [[0, 0.5], [1, 0.5], [1, 1]], "depth_m": 20, "depth_bottom_m": [[0, 4], [10, 6]]},
          {"type": "polygon", "points": [{"frame": 0, "points": [[0, 0], [0.1, 0], [0, 0.1]]}, {"frame": 8, "points": [[0.5, 0], [0.6, 0], [0.5, 0.1]]}]},
          {"type": "sky", "points": [[0, 0], [1, 0], [0.5, 0.2]]}])"},
                             presetSchema());
  // The bare pair list is stored in full form, as for section parameters.
  EXPECT_EQ(p.at("depth.layers.1.distance_m.interpolation"), "linear");
  EXPECT_DOUBLE_EQ(p.number("depth.layers.1.distance_m", 10), 20.0);
  EXPECT_DOUBLE_EQ(p.number("depth.layers.2.depth_bottom_m", 5), 5.0);
  EXPECT_FALSE(p.has("depth.layers.3.depth_bottom_m"));  // optional: stays absent
  EXPECT_DOUBLE_EQ(p.number("depth.layers.3.depth_m"), 10.0);

  auto problems = problemsOf(
      "moderate", {R"(depth.layers=[{"type": "card", "distance_m": {"keys": [[0, 10], [5, -1]]}},
          {"type": "polygon", "points": [[0, 0], [1, 1]]},
          {"type": "polygon", "depth_m": 3},
          {"type": "polygon", "points": [[0, 0], [1, 0], [1, "a"]]},
          {"type": "polygon", "points": [{"frame": 4, "points": [[0, 0], [1, 0], [1, 1]]}, {"frame": 2, "points": [[0, 0], [1, 0], [1, 1], [0, 1]]}]},
          {"type": "sky", "points": [[0, 0], [1, 0], [9, 1]], "x0": [[0, 0], [1, 0.5]]}])"});
  for (const auto& line : problems) std::cerr << line << "\n";
  EXPECT_TRUE(anyContains(problems, "/depth/layers/0/distance_m/keys/1/1: must be between 0.01"));
  EXPECT_TRUE(
      anyContains(problems, "/depth/layers/1/points: expected [[x, y], ...] with at least 3"));
  expectProblems(problems,
                 {"/depth/layers/2/points: missing", "/depth/layers/3/points/2: expected [x, y]",
                  "/depth/layers/4/points/1/frame: key frames must increase"});
  EXPECT_TRUE(
      anyContains(problems, "/depth/layers/4/points/1/points: every key needs the same number"));
  EXPECT_TRUE(anyContains(problems, "/depth/layers/5/points/2: each must be between -1 and 2"));
  EXPECT_EQ(problems.size(), 7u);  // the keyed x0 of the sky is fine
}

TEST(Preset, HashChangesWithKeys) {
  Preset a = Preset::resolve("moderate", {"rain.rate_mm_h=[[0,0],[48,40]]"}, presetSchema());
  Preset b = Preset::resolve("moderate", {"rain.rate_mm_h=[[0,0],[48,41]]"}, presetSchema());
  Preset c = Preset::resolve("moderate", {"rain.rate_mm_h=[[0,0],[47,40]]"}, presetSchema());
  Preset d = Preset::resolve(
      "moderate", {"rain.rate_mm_h={\"keys\": [[0,0],[48,40]], \"interpolation\": \"smooth\"}"},
      presetSchema());
  Preset same =
      Preset::resolve("moderate", {"rain.rate_mm_h={\"keys\": [[0,0],[48,40]]}"}, presetSchema());
  EXPECT_NE(a.hash(), b.hash());
  EXPECT_NE(a.hash(), c.hash());
  EXPECT_NE(a.hash(), d.hash());
  EXPECT_EQ(a.hash(), same.hash());  // the shorthand resolves to the same document
}

TEST(Preset, CameraPathAndLensKeys) {
  Preset plain = Preset::resolve("moderate", {}, presetSchema());
  EXPECT_TRUE(plain.at("camera.path").empty());
  EXPECT_DOUBLE_EQ(plain.number("camera.shutter_angle_deg"), 0.0);
  // The shipped camera: a video camera's small sensor at f/4, focused on the default depth's
  // backdrop, filming the rain with the plate's own shutter.
  EXPECT_DOUBLE_EQ(plain.number("camera.focus_m"), 20.0);
  EXPECT_DOUBLE_EQ(plain.number("camera.f_number"), 4.0);
  EXPECT_DOUBLE_EQ(plain.number("camera.sensor_width_mm"), 6.2);
  EXPECT_DOUBLE_EQ(plain.number("camera.exposure_s"), 0.0);  // the plate's shutter
  Camera base = Camera::fromFieldOfView(640, 360, 40, 0, 1.6);
  EXPECT_FALSE(cameraSettings(plain).path(base).moving());

  Preset moving = Preset::resolve(
      "moderate",
      {R"(camera.path=[{"frame": 0, "position_m": [0, 1.6, 0]}, {"frame": 10, "position_m": [2, 1.6, 0], "yaw_deg": 20}])"},
      presetSchema());
  EXPECT_DOUBLE_EQ(moving.number("camera.path.1.pitch_deg"), 0.0);  // defaults filled
  CameraPath path = cameraSettings(moving).path(base);
  EXPECT_TRUE(path.moving());
  EXPECT_NEAR(path.cameraAt(5).positionMeters.x(), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(path.cameraAt(5).focalPx, base.focalPx);

  auto problems = problemsOf(
      "moderate",
      {R"(camera.path=[{"frame": 5, "position_m": [0, 1, 0]}, {"frame": 5, "position_m": [0, 1]}, {"position_m": [0, 1, 0], "pitch_deg": 120}, {"type": "key", "frame": 9, "position_m": [0, 1, 0]}, 3])",
       "camera.shutter_angle_deg=400"});
  for (const auto& line : problems) std::cerr << line << "\n";
  expectProblems(problems,
                 {"/camera/path/1/frame: must increase strictly",
                  "/camera/path/1/position_m: expected [x, y, z]", "/camera/path/2/frame: missing",
                  "/camera/path/2/pitch_deg: must be between -90 and 90 deg",
                  "/camera/path/3/type: unknown key", "/camera/path/4: expected an object",
                  "/camera/shutter_angle_deg: must be between 0 and 360 deg"});
}

TEST(Preset, DescribeMentionsKeyframes) {
  const Schema schema = presetSchema();
  auto rain = std::find_if(schema.begin(), schema.end(),
                           [](const SectionSpec& s) { return s.name == "rain"; });
  ASSERT_NE(rain, schema.end());
  std::string text = describeSection(*rain);
  EXPECT_NE(text.find("rate_mm_h"), std::string::npos);
  EXPECT_NE(text.find("number|keys"), std::string::npos) << text;
  EXPECT_NE(text.find("\"interpolation\": \"linear|smooth|hold\""), std::string::npos) << text;
  auto camera = std::find_if(schema.begin(), schema.end(),
                             [](const SectionSpec& s) { return s.name == "camera"; });
  std::string cameraText = describeSection(*camera);
  EXPECT_NE(cameraText.find("each item:"), std::string::npos) << cameraText;
  EXPECT_NE(cameraText.find("position_m"), std::string::npos);
  // Keyframable list item fields (depth layers) are shown as such, with the syntax.
  auto depth = std::find_if(schema.begin(), schema.end(),
                            [](const SectionSpec& s) { return s.name == "depth"; });
  std::string depthText = describeSection(*depth);
  EXPECT_NE(depthText.find("item type \"polygon\""), std::string::npos) << depthText;
  EXPECT_NE(depthText.find("number|keys"), std::string::npos) << depthText;
  EXPECT_NE(depthText.find("\"interpolation\": \"linear|smooth|hold\""), std::string::npos);
}
