#pragma once
// The preset's "blur" section: its parameter table and its settings, read once from the preset.
#include "preset/param_table.h"
#include "preset/preset.h"

namespace pluvia {

SectionSpec blurSection();

struct BlurSettings {
  bool enabled = true;
  double sigmaPx = 0.0;  // Gaussian standard deviation in frame pixels; 0 leaves the plate sharp
};

BlurSettings blurSettings(const Preset& preset);

}  // namespace pluvia
