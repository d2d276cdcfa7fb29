#pragma once
// The preset's "splash" section: splashes where drops strike surfaces that face up
// (rain/splashes.h), at the rate of the rain section's drop flux.
#include "preset/param_table.h"
#include "preset/preset.h"

namespace pluvia {

SectionSpec splashSection();

struct SplashSettings {
  bool enabled = true;
  double minDiameterMm = 0.5;  // smaller drops make no visible splash
  double maxTiltDeg = 30.0;    // surfaces steeper than this take no splashes
  double opacity = 1.0;
  double minSizePx = 2.0;  // nearest crown size drawn: sets the farthest surface that splashes
  bool splatter = false;   // splatter texture flashes at the impacts (rain/splatter.h)
  double splatterSeconds = 0.04;
};

SplashSettings splashSettings(const Preset& preset);

}  // namespace pluvia
