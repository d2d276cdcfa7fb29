#pragma once
// The preset's "fog" section: its parameter table and its settings, read once from the preset.
#include <array>
#include <string>

#include "preset/preset.h"
#include "preset/settings_table.h"

namespace pluvia {

// fog.model: one airlight colour, or the environment scattered per view direction.
enum class FogModel { Exponential, Skylight };
// fog.color_source: the airlight of the exponential model.
enum class FogColorSource { Horizon, Average, Constant };

struct FogSettings {
  bool enabled = true;
  bool overRain = false;  // also on a plate shot in rain (stages/clip_plate_rain.h)
  // Exponential: alpha = 1 - exp(-density * depth) toward one airlight colour; Skylight: the
  // environment scattered by rain and fog per view direction (optics/skylight_scattering.h).
  FogModel model = FogModel::Exponential;
  double densityPerMeter = 0.0;  // extinction; 0: no fog
  FogColorSource colorSource = FogColorSource::Horizon;
  std::array<float, 3> constantRgb{0.5f, 0.5f, 0.5f};  // linear, for FogColorSource::Constant
  int skylightTableWidth = 64;  // the skylight model's table of in-scattering per direction
};

// The section's table (`section()`: the StageInfo's spec) and its settings read from a
// resolved preset.
const SettingsTable<FogSettings>& fogTable();
FogSettings fogSettings(const Preset& preset);

}  // namespace pluvia
