#pragma once
// The preset's "color" section: the OpenColorIO colour spaces at the two ends of the render. The
// render session converts with it; the lighting stage reads the input space of its stitched
// frames from it.
#include <string>

#include <nlohmann/json.hpp>

#include "preset/param_table.h"
#include "preset/preset.h"

namespace pluvia {

// The section's parameter table (part of presetSchema(), stages/registry.h).
SectionSpec colorSection();

struct ColorSettings {
  std::string inputSpace = "auto";  // auto: linear-rec709 for float files, sRGB otherwise
  std::string workingSpace = "linear-rec709";
  std::string outputSpace = "auto";  // auto: linear-rec709 for EXR, sRGB otherwise
  std::string configPath;            // an .ocio config; empty: pluvia's built-in one
  // The section as the preset resolved it, for the cache keys of per-clip analyses that depend
  // on it (see CameraSettings::resolved).
  nlohmann::json resolved;
};

ColorSettings colorSettings(const Preset& preset);

}  // namespace pluvia
