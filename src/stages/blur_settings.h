#pragma once
// The preset's "blur" section: its parameter table and its settings, read once from the preset.
#include "preset/preset.h"
#include "preset/settings_table.h"

namespace pluvia {

struct BlurSettings {
  bool enabled = true;
  bool overRain = false;  // also on a plate shot in rain (stages/clip_plate_rain.h)
  double sigmaPx = 0.0;   // Gaussian standard deviation in frame pixels; 0 leaves the plate sharp
  // The depth at which 63 % of the blur is mixed in (stages/depth_grading.h); 0: every pixel
  // alike.
  double distanceMeters = 30.0;
};

// The section's table (`section()`: the StageInfo's spec) and its settings read from a
// resolved preset.
const SettingsTable<BlurSettings>& blurTable();
BlurSettings blurSettings(const Preset& preset);

}  // namespace pluvia
