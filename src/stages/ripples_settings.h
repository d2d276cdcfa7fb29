#pragma once
// The preset's "ripples" section: rings on level ground where drops strike it (rain/ripples.h),
// at the rain's impact rate.
#include "preset/preset.h"
#include "preset/settings_table.h"

namespace pluvia {

struct RipplesSettings {
  // Off by default until the rings read: mirroring the environment alone, a puddle seen from above
  // under an even sky changes by under a code (issue 58: the plate's own reflection must move).
  bool enabled = false;
  double minDiameterMm = 0.5;  // smaller drops raise no visible ring
  double maxTiltDeg = 5.0;     // standing water is level
};

const SettingsTable<RipplesSettings>& ripplesTable();
RipplesSettings ripplesSettings(const Preset& preset);

}  // namespace pluvia
