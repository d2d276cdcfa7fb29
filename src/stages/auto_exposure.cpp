#include "stages/auto_exposure.h"

#include <cmath>
#include <exception>
#include <string>

#include <fmt/format.h>

#include "stages/clip_still.h"
#include "stages/plate_lights.h"
#include "util/log.h"

namespace pluvia {

namespace {

// The shutter the plate's files state (EXIF or EXR ExposureTime, OpenImageIO's name: stills and
// sequences from photo and phone cameras carry it), in seconds; 0 when absent or implausible.
double plateExposureSeconds(const ClipContext& clip) {
  if (!clip.clip) return 0.0;
  const auto it = clip.clip->metadata.find("ExposureTime");
  if (it == clip.clip->metadata.end()) return 0.0;
  try {
    const double seconds = std::stod(it->second);
    return std::isfinite(seconds) && seconds >= 1e-5 && seconds <= 1.0 ? seconds : 0.0;
  } catch (const std::exception&) {
    return 0.0;
  }
}

}  // namespace

void resolveAutoExposure(CameraSettings& camera, ClipContext& clip, const char* stage) {
  if (!camera.autoExposure()) return;
  if (const double stated = plateExposureSeconds(clip); stated > 0.0) {
    camera.autoExposureSeconds = stated;
    log::info(
        fmt::format("{}: camera.exposure_s 0 (auto): 1/{:.0f} s (the plate's metadata: "
                    "ExposureTime {:g} s)",
                    stage, 1.0 / stated, stated));
    return;
  }
  const bool night = isNightPlate(plateLuminance(clipStill(clip)));
  camera.autoExposureSeconds = night ? 0.5 / clip.fps : kDaylightExposureSeconds;
  log::info(fmt::format("{}: camera.exposure_s 0 (auto): 1/{:.0f} s ({})", stage,
                        1.0 / camera.autoExposureSeconds,
                        night ? "a night plate: the 180-degree shutter" : "a day plate"));
}

}  // namespace pluvia
