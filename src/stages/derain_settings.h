#pragma once
// The preset's "derain" section: its parameter table and its settings, read once from the preset.
#include <string>

#include <nlohmann/json.hpp>

#include "preset/preset.h"
#include "preset/settings_table.h"

namespace pluvia {

struct DerainSettings {
  bool enabled = true;
  std::string input;  // rain footage; empty: the render input
  int frames = 20;    // solved together, from the footage's first frame
  int strokeCount = 64;
  // The section as the preset resolved it (filled by SettingsTable::read): the cache key of the cut
  // strokes hashes it (see CameraSettings::resolved).
  nlohmann::json resolved;
};

// The section's table (`section()`: the StageInfo's spec) and its settings read from a
// resolved preset.
const SettingsTable<DerainSettings>& derainTable();
DerainSettings derainSettings(const Preset& preset);

}  // namespace pluvia
