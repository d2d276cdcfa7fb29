#pragma once
// The preset's "fog" section: its parameter table and its settings, read once from the preset.
#include <array>
#include <string>

#include "preset/param_table.h"
#include "preset/preset.h"

namespace pluvia {

SectionSpec fogSection();

struct FogSettings {
  bool enabled = true;
  double densityPerMeter = 0.0;                        // extinction; 0: no fog
  std::string colorSource = "horizon";                 // "horizon" | "average" | "constant"
  std::array<float, 3> constantRgb{0.5f, 0.5f, 0.5f};  // linear, for colorSource "constant"
};

FogSettings fogSettings(const Preset& preset);

}  // namespace pluvia
