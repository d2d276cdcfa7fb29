// The typed settings of each preset section, read once from a resolved preset
// (stages/<section>_settings.h, pipeline/camera_settings.h, pipeline/color_settings.h), and the
// table-row builders they are declared with (preset/param_table.h).
#include <fstream>

#include <gtest/gtest.h>

#include "pipeline/camera_settings.h"
#include "pipeline/color_settings.h"
#include "pipeline/frame_metadata.h"
#include "preset/param_table.h"
#include "preset/preset.h"
#include "stages/blur_settings.h"
#include "stages/darken_settings.h"
#include "stages/depth_settings.h"
#include "stages/derain_settings.h"
#include "stages/fog_settings.h"
#include "stages/lighting_settings.h"
#include "stages/lights_settings.h"
#include "stages/rain_settings.h"
#include "stages/rainbow_settings.h"
#include "stages/registry.h"
#include "stages/splash_settings.h"
#include "test_support.h"

using namespace pluvia;

namespace {

Preset resolve(const std::string& name, const std::vector<std::string>& sets = {}) {
  return Preset::resolve(name, sets, presetSchema());
}

}  // namespace

TEST(ParamBuilders, DefaultsKeepTheirJsonType) {
  // The default's JSON type reaches the resolved preset (its hash) and `pluvia describe`.
  EXPECT_TRUE(numberParam("x_m", 3, {0, 9}, "m", "").defaultValue.is_number_float());
  EXPECT_EQ(numberParam("x_m", 3, {0, 9}, "m", "").defaultValue.dump(), "3.0");
  EXPECT_TRUE(integerParam("n", 3, {0, 9}, "", "").defaultValue.is_number_integer());
  EXPECT_EQ(integerParam("n", 3, {0, 9}, "", "").defaultValue.dump(), "3");
  const ParamSpec range = numberParam("x_m", 3, {-1, 2}, "m", "help");
  EXPECT_EQ(range.minValue, -1);
  EXPECT_EQ(range.maxValue, 2);
  EXPECT_EQ(range.units, "m");
  EXPECT_EQ(range.help, "help");
  const ParamSpec field = required(numberParam("frame", 0, {}, "", ""));
  EXPECT_TRUE(field.required);
  EXPECT_TRUE(field.defaultValue.is_null());
  EXPECT_TRUE(std::isinf(field.minValue) && field.minValue < 0);
  const ParamSpec choice = enumParam("mode", "a", {"a", "b"}, "");
  EXPECT_EQ(choice.type, ParamType::Enum);
  EXPECT_EQ(choice.choices, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(enabledParam().defaultValue, true);
}

// A default is written in a section's row and again in its settings struct: the two must agree
// (read from a preset that sets nothing, every row gives its own default).
TEST(SectionSettings, EveryRowsDefaultIsTheStructsDefault) {
  const auto folder = test::freshTempDir("struct_defaults");
  std::ofstream(folder / "nothing.json") << R"({"pluvia": 1})";
  const Preset defaults = resolve((folder / "nothing.json").string());
  std::vector<std::string> differing;
  auto check = [&](const auto& table) {
    for (const std::string& key : table.keysWhoseStructDefaultDiffers(defaults))
      differing.push_back(key);
  };
  check(cameraTable());
  check(colorTable());
  check(derainTable());
  check(lightingTable());
  check(depthTable());
  check(darkenTable());
  check(blurTable());
  check(fogTable());
  check(rainTable());
  check(rainbowTable());
  check(lightsTable());
  check(splashTable());
  EXPECT_TRUE(differing.empty()) << ::testing::PrintToString(differing);
}

TEST(SectionSettings, EveryShippedPresetBuildsEverySection) {
  // A key misspelled in a settings function would throw "preset has no key" here.
  ASSERT_GE(shippedPresetNames().size(), 7u);
  for (const std::string& name : shippedPresetNames()) {
    const Preset p = resolve(name);
    EXPECT_NO_THROW({
      cameraSettings(p);
      colorSettings(p);
      derainSettings(p);
      lightingSettings(p);
      depthSettings(p);
      darkenSettings(p);
      blurSettings(p);
      fogSettings(p);
      rainSettings(p);
    }) << name;
  }
}

TEST(SectionSettings, ValuesSetInThePresetReachTheirFields) {
  const Preset p = resolve("moderate", {"fog.density=0.02",
                                        "fog.color_source=constant",
                                        "fog.color=[1,2,3]",
                                        "rain.seed=7",
                                        "rain.distribution=gamma",
                                        "rain.velocity=gunn_kinzer",
                                        "rain.max_drops=1234",
                                        "rain.cells.count=3",
                                        "rain.wind.eddies=0.5",
                                        "blur.sigma_px=2.5",
                                        "darken.amount=0.25",
                                        "derain.count=9",
                                        "lighting.source=stitch",
                                        "lighting.every=7",
                                        "depth.source=file",
                                        "depth.file_encoding=inverse",
                                        "depth.max_frames=55",
                                        "color.output=sRGB",
                                        "camera.fov_deg=50",
                                        "camera.height_m=9",
                                        "camera.fps=25"});
  const FogSettings fog = fogSettings(p);
  EXPECT_DOUBLE_EQ(fog.densityPerMeter, 0.02);
  EXPECT_EQ(fog.colorSource, FogColorSource::Constant);
  EXPECT_EQ(fog.constantRgb, (std::array<float, 3>{1, 2, 3}));
  const RainSettings rain = rainSettings(p);
  EXPECT_EQ(rain.seed, 7u);
  EXPECT_EQ(rain.distribution, rain::SizeDistribution::Gamma);
  EXPECT_EQ(rain.velocity, rain::VelocityModel::GunnKinzer);
  EXPECT_EQ(rain.maxDrops, 1234);
  EXPECT_EQ(rain.cells.count, 3);
  EXPECT_DOUBLE_EQ(rain.wind.eddies, 0.5);
  EXPECT_DOUBLE_EQ(blurSettings(p).sigmaPx, 2.5);
  EXPECT_DOUBLE_EQ(darkenSettings(p).amount, 0.25);
  EXPECT_EQ(derainSettings(p).strokeCount, 9);
  EXPECT_EQ(lightingSettings(p).source, LightingSource::Stitch);
  EXPECT_EQ(lightingSettings(p).everyFrames, 7);
  EXPECT_EQ(depthSettings(p).fileEncoding, "inverse");
  EXPECT_EQ(depthSettings(p).maxFrames, 55);
  EXPECT_EQ(colorSettings(p).outputSpace, "sRGB");
  const CameraSettings camera = cameraSettings(p);
  EXPECT_DOUBLE_EQ(camera.fovDeg, 50);
  EXPECT_DOUBLE_EQ(camera.heightMeters, 9);
  EXPECT_DOUBLE_EQ(camera.framesPerSecond, 25);
  // The section as resolved, for cache keys: the JSON as given, an integer stays one.
  EXPECT_EQ(camera.resolved.at("fov_deg").dump(), "50");
}

TEST(SectionSettings, KeyframedValuesAreRampsAtEveryFrame) {
  const Preset p =
      resolve("moderate", {"rain.rate_mm_h=[[0,0],[10,20]]",
                           "rain.opacity={\"keys\":[[4,1],[8,3]],\"interpolation\":\"hold\"}",
                           "camera.exposure_s=[[0,0.01],[10,0.03]]"});
  const RainSettings rain = rainSettings(p);
  // Linear between keys, held outside them: 2 mm/h per frame.
  EXPECT_DOUBLE_EQ(rain.rateMmPerHour.valueAt(-3), 0.0);
  EXPECT_DOUBLE_EQ(rain.rateMmPerHour.valueAt(5), 10.0);
  EXPECT_DOUBLE_EQ(rain.rateMmPerHour.valueAt(7.5), 15.0);
  EXPECT_DOUBLE_EQ(rain.rateMmPerHour.valueAt(40), 20.0);
  EXPECT_DOUBLE_EQ(rain.rateMmPerHour.maxValue(), 20.0);
  EXPECT_DOUBLE_EQ(rain.opacity.valueAt(7.9), 1.0);  // hold
  EXPECT_DOUBLE_EQ(rain.opacity.valueAt(8), 3.0);
  // A plain number is a constant ramp.
  EXPECT_FALSE(rain.densityScale.animated());
  EXPECT_DOUBLE_EQ(rain.densityScale.valueAt(123), p.number("rain.density_scale"));
  // The same values the preset gives frame by frame.
  for (double frame : {0.0, 2.5, 9.0, 11.0})
    EXPECT_DOUBLE_EQ(rain.rateMmPerHour.valueAt(frame), p.number("rain.rate_mm_h", frame));
  const CameraSettings camera = cameraSettings(p);
  EXPECT_DOUBLE_EQ(camera.exposureSecondsAt(24.0, 5.0), 0.02);
}

TEST(SectionSettings, ShutterAngleOverridesTheExposure) {
  const CameraSettings camera = cameraSettings(
      resolve("moderate", {"camera.shutter_angle_deg=180", "camera.exposure_s=0.1"}));
  EXPECT_DOUBLE_EQ(camera.exposureSecondsAt(24.0, 0.0), 1.0 / 48.0);  // 180 / 360 / 24
  EXPECT_DOUBLE_EQ(camera.exposureSecondsAt(25.0, 99.0), 1.0 / 50.0);
}

TEST(SectionSettings, CameraPathKeysAndBaseCamera) {
  const Preset p = resolve(
      "moderate",
      {"camera.fov_deg=90", "camera.tilt_deg=10", "camera.height_m=2",
       R"(camera.path=[{"frame": 0, "position_m": [0, 1, 0]}, {"frame": 4, "position_m": [4, 1, 0], "yaw_deg": 8}])"});
  const CameraSettings camera = cameraSettings(p);
  ASSERT_EQ(camera.pathKeys.size(), 2u);
  EXPECT_DOUBLE_EQ(camera.pathKeys[1].first, 4.0);
  EXPECT_DOUBLE_EQ(camera.pathKeys[1].second.yawDeg, 8.0);
  const Camera base = camera.base(200, 100);
  // 90 degrees across 200 px: f = 100 / tan(45 deg) = 100 px.
  EXPECT_NEAR(base.focalPx, 100.0, 1e-9);
  const CameraPath path = camera.path(base);
  EXPECT_TRUE(path.moving());
  EXPECT_NEAR(path.cameraAt(2).positionMeters.x(), 2.0, 1e-12);
  EXPECT_FALSE(cameraSettings(resolve("moderate")).path(base).moving());
}

TEST(SectionSettings, FramesRecordTheSeedThroughTheRainStage) {
  const Preset p = resolve("moderate", {"rain.seed=42"});
  const auto metadata = frameMetadata(p, allStages());
  EXPECT_EQ(metadata.at("pluvia:seed"), "42");
  EXPECT_EQ(metadata.at("pluvia:presetHash"), p.hash());
  // Without the stages, no stage adds its part.
  EXPECT_EQ(frameMetadata(p, {}).count("pluvia:seed"), 0u);
}
