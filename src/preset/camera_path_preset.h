#pragma once
// The preset's camera.path as a CameraPath. Lives with the presets (which link pluvia_geometry),
// so that geometry knows nothing of presets.
#include "geometry/camera_path.h"
#include "preset/preset.h"

namespace pluvia {

// camera.path items {"frame": F, "position_m": [x, y, z], "yaw_deg": .., "pitch_deg": ..,
// "roll_deg": ..} as keys over `base`'s intrinsics; an empty path (the default) is
// CameraPath::fixed(base), the static camera built from fov_deg, tilt_deg and height_m.
CameraPath cameraPathFromPreset(const Preset& preset, const Camera& base);

}  // namespace pluvia
