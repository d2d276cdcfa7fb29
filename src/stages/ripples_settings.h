#pragma once
// The preset's "ripples" section: rings on level ground where drops strike it (rain/ripples.h),
// at the rain's impact rate.
#include "preset/preset.h"
#include "preset/settings_table.h"

namespace pluvia {

struct RipplesSettings {
  // Off by default: the plate's own reflection displaced by the rings reads as rippled water but
  // too strongly (the ring's first amplitude is a look), and it costs 11 times the rain stage.
  bool enabled = false;
  double minDiameterMm = 0.5;  // smaller drops raise no visible ring
  double maxTiltDeg = 5.0;     // standing water is level
};

const SettingsTable<RipplesSettings>& ripplesTable();
RipplesSettings ripplesSettings(const Preset& preset);

}  // namespace pluvia
