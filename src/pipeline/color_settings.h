#pragma once
// The preset's "color" section: the OpenColorIO colour spaces at the two ends of the render. The
// render session converts with it; the lighting stage reads the input space of its stitched
// frames from it.
#include <string>

#include <nlohmann/json.hpp>

#include "preset/preset.h"
#include "preset/settings_table.h"

namespace pluvia {

struct ColorSettings {
  std::string inputSpace =
      "auto";  // auto: scene_linear for float files, the config's sRGB otherwise
  std::string workingSpace = "scene_linear";  // a name, alias or role of the config
  std::string outputSpace = "auto";  // auto: the working space for EXR, the config's sRGB otherwise
  std::string configPath;            // an .ocio config; empty: $OCIO, else pluvia's built-in one
  // The section as the preset resolved it (filled by SettingsTable::read), for the cache keys of
  // per-clip analyses that depend on it (see CameraSettings::resolved).
  nlohmann::json resolved;
};

// The section's table (its SectionSpec is part of presetSchema(), stages/registry.h) and its
// settings read from a resolved preset.
const SettingsTable<ColorSettings>& colorTable();
ColorSettings colorSettings(const Preset& preset);

}  // namespace pluvia
