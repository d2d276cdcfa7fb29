#pragma once
// The preset's "lighting" section (the environment stage's): its parameter table and its
// settings, read once from the preset.
#include <array>
#include <string>

#include <nlohmann/json.hpp>

#include "envmap/clip_environment.h"
#include "envmap/panorama.h"
#include "preset/preset.h"
#include "preset/settings_table.h"

namespace pluvia {

// lighting.source: where the environment that lights the drops comes from.
enum class LightingSource { Frame, FrameAverage, Constant, Hdr, Stitch };

struct LightingSettings {
  bool enabled = true;
  LightingSource source = LightingSource::Frame;
  envmap::StitchMotion motion = envmap::StitchMotion::Auto;  // stitch
  int everyFrames = 5;  // stitch, loom: a panorama every N frames
  int panFrames = 24;   // stitch, pan: frames stitched
  envmap::UnseenFill unseenFill = envmap::UnseenFill::SkyModel;  // stitch
  // Light sources the footage saturated, as given: items of type "direction" or "region"
  // (envmap::parseLights reads them; region fields are in frame pixels).
  nlohmann::json lights = nlohmann::json::array();
  std::string hdrPath;                                 // source hdr
  double intensity = 1.0;                              // scale on the HDR's radiance
  std::array<float, 3> constantRgb{0.5f, 0.5f, 0.5f};  // source constant, linear
  int sampleFrames = 8;                                // source frame_average
  // The section as the preset resolved it (filled by SettingsTable::read): the environment's cache
  // key hashes it (see CameraSettings::resolved).
  nlohmann::json resolved;
};

// The section's table (`section()`: the StageInfo's spec) and its settings read from a
// resolved preset.
const SettingsTable<LightingSettings>& lightingTable();
LightingSettings lightingSettings(const Preset& preset);

}  // namespace pluvia
