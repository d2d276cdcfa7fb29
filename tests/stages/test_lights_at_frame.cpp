// The lights stage's own part: the preset's lights placed in each frame's camera space
// (stages/lights_at_frame.h), and the stage left out of the plan when there are none.
#include <gtest/gtest.h>

#include "geometry/camera.h"
#include "preset/preset.h"
#include "stages/lights_at_frame.h"
#include "stages/lights_settings.h"
#include "stages/registry.h"

using namespace pluvia;

namespace {

Camera testCamera() {
  return Camera::fromFieldOfView(96, 64, 60.0, 0.0, 1.6);
}

}  // namespace

TEST(LightsAtFrame, WorldLightsFollowTheCamera) {
  const Preset preset = Preset::resolve(
      "base",
      {R"(lights.list=[{"type":"point","frame":"world","x_m":1,"y_m":3,"z_m":-10,"intensity":50},)"
       R"({"type":"spot","x_m":0,"y_m":0,"z_m":-5,"dir_x":0,"dir_y":-1,"dir_z":0}])"},
      presetSchema());
  LightsSettings settings = lightsSettings(preset);
  ASSERT_EQ(settings.lights.size(), 2u);
  Camera camera = testCamera();  // at (0, 1.6, 0)
  camera.positionMeters = {2.0, 1.6, 0.0};
  const auto lights = lightsAtFrame(settings, camera, 0.0);
  EXPECT_NEAR(lights[0].positionMeters[0], -1.0, 1e-12);
  EXPECT_NEAR(lights[0].positionMeters[1], 1.4, 1e-12);
  EXPECT_NEAR(lights[0].positionMeters[2], -10.0, 1e-12);
  EXPECT_NEAR(lights[0].rgbIntensity[0], 50.0 * 1.0, 1e-12);
  // A spot with no axis is refused where the preset is read (as `pluvia validate` says).
  const Preset noAxis = Preset::resolve(
      "base", {R"(lights.list=[{"type":"spot","dir_x":0,"dir_y":0,"dir_z":1e-12}])"},
      presetSchema());
  EXPECT_THROW(lightsSettings(noAxis), Error);
}

TEST(LightsAtFrame, PlanSkipsTheStageWithoutLights) {
  const StageInfo* info = findStage("lights");
  ASSERT_NE(info, nullptr);
  // Nothing listed and nothing looked for in the plate: skipped.
  const Preset none = Preset::resolve("base", {"lights.find=off"}, presetSchema());
  EXPECT_NE(info->noOpReason(none).find("no lights"), std::string::npos);
  // Nothing listed, but lamps may be found in the plate (the default): it runs.
  const Preset looking = Preset::resolve("base", {}, presetSchema());
  EXPECT_EQ(info->noOpReason(looking), "");
  const Preset one = Preset::resolve("base", {R"(lights.list=[{"type":"point"}])"}, presetSchema());
  EXPECT_EQ(info->noOpReason(one), "");
}
