#pragma once
// The preset's "darken" section: its parameter table and its settings, read once from the preset.
#include "preset/param_table.h"
#include "preset/preset.h"

namespace pluvia {

SectionSpec darkenSection();

struct DarkenSettings {
  bool enabled = true;
  double amount = 0.0;     // blend toward luminance; 0 leaves the plate as it is
  double darkening = 0.5;  // brightness lost at amount 1: out *= 1 - amount * darkening
};

DarkenSettings darkenSettings(const Preset& preset);

}  // namespace pluvia
