#pragma once
// The preset's "splash" section: splashes where drops strike surfaces that face up
// (rain/splashes.h), at the rate of the rain section's drop flux.
#include "preset/preset.h"
#include "preset/settings_table.h"

namespace pluvia {

struct SplashSettings {
  bool enabled = true;
  double minDiameterMm = 0.5;  // smaller drops make no visible splash
  double maxTiltDeg = 30.0;    // surfaces steeper than this take no splashes
  double opacity = 1.0;
  double minSizePx = 2.0;  // nearest crown size drawn: sets the farthest surface that splashes
  bool splatter = false;   // splatter texture flashes at the impacts (rain/splatter.h)
  double splatterMs = 40.0;
};

// The section's table (`section()`: the StageInfo's spec) and its settings read from a
// resolved preset.
const SettingsTable<SplashSettings>& splashTable();
SplashSettings splashSettings(const Preset& preset);

}  // namespace pluvia
