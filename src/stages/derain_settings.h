#pragma once
// The preset's "derain" section: its parameter table and its settings, read once from the preset.
#include <string>

#include <nlohmann/json.hpp>

#include "preset/param_table.h"
#include "preset/preset.h"

namespace pluvia {

SectionSpec derainSection();

struct DerainSettings {
  bool enabled = true;
  std::string input;  // rain footage; empty: the render input
  int frames = 20;    // solved together, from the footage's first frame
  int strokeCount = 64;
  // The section as the preset resolved it: the cache key of the cut strokes hashes it (see
  // CameraSettings::resolved).
  nlohmann::json resolved;
};

DerainSettings derainSettings(const Preset& preset);

}  // namespace pluvia
