#pragma once
// The preset's "darken" section: its parameter table and its settings, read once from the preset.
#include "preset/preset.h"
#include "preset/settings_table.h"

namespace pluvia {

struct DarkenSettings {
  bool enabled = true;
  bool overRain = false;   // also on a plate shot in rain (stages/clip_plate_rain.h)
  double amount = 0.0;     // blend toward luminance; 0 leaves the plate as it is
  double darkening = 0.5;  // brightness lost at amount 1: out *= 1 - amount * darkening
  // The depth at which 63 % of the amount applies (stages/depth_grading.h); 0: every pixel alike.
  double distanceMeters = 30.0;
};

// The section's table (`section()`: the StageInfo's spec) and its settings read from a
// resolved preset.
const SettingsTable<DarkenSettings>& darkenTable();
DarkenSettings darkenSettings(const Preset& preset);

}  // namespace pluvia
