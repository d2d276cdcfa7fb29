#pragma once
// The preset's "rainbow" section: the primary and secondary bows of a sun behind the camera,
// seen in the rain (optics/rainbow.h).
#include <array>
#include <string>

#include "preset/preset.h"
#include "preset/settings_table.h"

namespace pluvia {

// rainbow.sun: the environment's brightest spot, or the direction the preset gives.
enum class RainbowSun { Environment, Direction };

struct RainbowSettings {
  bool enabled = true;
  RainbowSun sunSource = RainbowSun::Environment;
  double sunElevationDeg = 30.0;  // RainbowSun::Direction
  double sunAzimuthDeg = 180.0;   // from world -Z toward +X; 180: behind the camera
  std::array<float, 3> sunIrradianceRgb{3.0f, 3.0f, 3.0f};  // RainbowSun::Direction, linear
  double showerExtentMeters = 2000.0;  // far edge of the rain shower along a ray to the sky
  double strength = 1.0;               // artist scale on the physical radiance
};

// The section's table (`section()`: the StageInfo's spec) and its settings read from a
// resolved preset.
const SettingsTable<RainbowSettings>& rainbowTable();
RainbowSettings rainbowSettings(const Preset& preset);

}  // namespace pluvia
