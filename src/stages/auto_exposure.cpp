#include "stages/auto_exposure.h"

#include <fmt/format.h>

#include "stages/clip_still.h"
#include "stages/plate_lights.h"
#include "util/log.h"

namespace pluvia {

void resolveAutoExposure(CameraSettings& camera, ClipContext& clip, const char* stage) {
  if (!camera.autoExposure()) return;
  const bool night = isNightPlate(plateLuminance(clipStill(clip)));
  camera.autoExposureSeconds = night ? 0.5 / clip.fps : kDaylightExposureSeconds;
  log::info(fmt::format("{}: camera.exposure_s 0 (auto): 1/{:.0f} s ({})", stage,
                        1.0 / camera.autoExposureSeconds,
                        night ? "a night plate: the 180-degree shutter" : "a day plate"));
}

}  // namespace pluvia
