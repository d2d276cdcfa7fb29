#pragma once
// The preset's "depth" section: its parameter table and its settings, read once from the preset.
#include <string>

#include <nlohmann/json.hpp>

#include "preset/preset.h"
#include "preset/settings_table.h"

namespace pluvia {

// depth.source: where each frame's depth comes from.
enum class DepthSource { Auto, Layers, Colmap, File, None };
// depth.fallback: what a failed COLMAP tracking does.
enum class DepthFallback { Error, Layers };
// depth.scale: where COLMAP's metric scale comes from.
enum class DepthScale { CameraHeight, FirstFrameDepth };

struct DepthSettings {
  bool enabled = true;
  DepthSource source = DepthSource::Auto;
  // The manual layers as given (geometry/depth_layers.h rasterises them; numbers may be keys).
  nlohmann::json layers = nlohmann::json::array({{{"type", "ground"}}});
  double backdropMeters = 20.0;  // auto: what is neither sky nor ground
  DepthFallback fallback = DepthFallback::Error;
  int frameStep = 0;         // colmap: every Nth frame tracked; 0: by parallax
  int maxFrames = 200;       // colmap
  int colmapImagePx = 1600;  // colmap: longest side of the frames features are found on
  std::string colmapModel;   // colmap: a text model to read instead of running COLMAP
  std::string colmapDense;   // colmap: a dense workspace whose depth maps are used
  DepthScale scale = DepthScale::CameraHeight;  // colmap
  double firstFrameDepthMeters = 10.0;          // colmap, scale first_frame_depth
  std::string file;                             // file: the depth sequence
  std::string fileEncoding = "z_m";             // file: z_m | inverse | normalized
  double fileScale = 1.0;
  double fileNearMeters = 1.0;
  double fileFarMeters = 100.0;
  // The section as the preset resolved it (filled by SettingsTable::read): the COLMAP tracking's
  // cache key hashes the values it depends on from it (see CameraSettings::resolved).
  nlohmann::json resolved;
};

// The section's table (`section()`: the StageInfo's spec) and its settings read from a
// resolved preset.
const SettingsTable<DepthSettings>& depthTable();
DepthSettings depthSettings(const Preset& preset);

}  // namespace pluvia
