#pragma once
// The preset's "wet_ground" section: the ground the rain falls on, darkened and glossed by its
// film of water (rain/wet_ground.h).
#include "preset/preset.h"
#include "preset/settings_table.h"

namespace pluvia {

struct WetGroundSettings {
  bool enabled = true;
  bool overRain = false;  // also on a plate shot in rain, whose ground is wet already
  double wetness = 1.0;   // share of the ground under a film: 0 dry, 1 soaked
  // The film's mirror: 1 Fresnel's, 0 none (the default: see wet_ground_settings.cpp; never over a
  // guessed depth).
  double gloss = 0.0;
  double maxTiltDeg = 30.0;  // fully wet up to this tilt from level
  double fadeDeg = 15.0;     // and dry again this much steeper
};

const SettingsTable<WetGroundSettings>& wetGroundTable();
WetGroundSettings wetGroundSettings(const Preset& preset);

}  // namespace pluvia
