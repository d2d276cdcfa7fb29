#pragma once
// camera.exposure_s 0: the shutter a video camera's auto exposure takes for the plate. By day,
// without neutral-density filters, it shortens the shutter against the light: about 1/1000 s
// for a phone or camcorder (f/1.8-2.8 at base ISO) in overcast daylight. NTURain's brightest
// streaks say the same: about 3 times as long as wide, so the drop moved about twice its own
// diameter during the exposure (2 mm at 6.5 m/s: 1/1000 s). At night
// it opens to the 180-degree shutter, half the frame time (1/50 s at 25 fps), where drops far
// from the lamps fade into the dark and those near them draw long glints.
#include "pipeline/camera_settings.h"
#include "pipeline/stage.h"

namespace pluvia {

inline constexpr double kDaylightExposureSeconds = 1.0 / 1000.0;

// Sets camera.autoExposureSeconds from the plate's metadata (ExposureTime, when its files state
// it), else from the clip's still (stages/plate_lights.h: a night plate)
// when the camera leaves its exposure to auto; logs it once per stage.
void resolveAutoExposure(CameraSettings& camera, ClipContext& clip, const char* stage);

}  // namespace pluvia
