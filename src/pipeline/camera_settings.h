#pragma once
// The preset's "camera" section: the virtual camera that films the rain. A shared section: the
// render session builds the clip's camera from it, and the stages that need the camera (depth,
// lighting, rain) take a CameraSettings, never the preset's camera keys.
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/camera.h"
#include "geometry/camera_path.h"
#include "preset/preset.h"
#include "preset/ramp.h"
#include "preset/settings_table.h"

namespace pluvia {

struct CameraSettings {
  double fovDeg = 36.0;          // horizontal field of view
  Ramp exposureSeconds{0.0};     // 0: the plate's (plateShutterSeconds)
  double shutterAngleDeg = 0.0;  // > 0: overrides exposureSeconds (angle / 360 / fps)
  double framesPerSecond = 0.0;  // 0: the clip's
  double tiltDeg = 0.0;          // positive looking down
  double heightMeters = 1.6;
  double focusMeters = 20.0;  // 0: no defocus
  double fNumber = 11.0;      // 0: pinhole
  double sensorWidthMm = 36.0;
  // fovDeg, fNumber and sensorWidthMm replaced by what the plate's files state of its lens
  // (pipeline/plate_lens.h), where they state it.
  bool lensFromPlate = true;
  // camera.path: poses over clip frames; empty: a static camera from tiltDeg and heightMeters.
  std::vector<std::pair<double, CameraPose>> pathKeys;
  // The section as the preset resolved it (filled by SettingsTable::read): per-clip analyses that
  // depend on the camera hash it into their cache keys (the JSON text, so a key stays the same
  // however a number was written).
  nlohmann::json resolved;
  // The plate camera's shutter time, where exposureSeconds is 0: set by the stages that film the
  // rain (stages/plate_shutter.h) before any frame.
  double plateShutterSeconds = 0.0;

  // The camera of a frame `width` x `height` px: fovDeg, tiltDeg and heightMeters.
  Camera base(int width, int height) const;
  // The path over `base`'s intrinsics: the keys, or CameraPath::fixed(base) without keys.
  CameraPath path(const Camera& base) const;
  // The shutter time at clip frame `frame` of a clip at `fps`: the angle when given, else the
  // exposure, else (exposure 0) the plate's.
  double exposureSecondsAt(double fps, double frame) const;
  // Throws pluvia::Error when an exposure key is longer than a frame at `fps`.
  void checkExposureFits(double fps) const;
  // Whether some frame's exposure is left to the plate's shutter (exposure_s 0, no angle).
  bool shutterFromPlate() const;
  // The frame rate a render works and writes at: camera.fps when given, else the clip's. A farm
  // job takes it too, so that its assembled movie runs at the one-machine render's rate.
  double framesPerSecondOf(double clipFramesPerSecond) const;
};

// The section's table (its SectionSpec is part of presetSchema(), stages/registry.h) and its
// settings read from a resolved preset.
const SettingsTable<CameraSettings>& cameraTable();
CameraSettings cameraSettings(const Preset& preset);

}  // namespace pluvia
