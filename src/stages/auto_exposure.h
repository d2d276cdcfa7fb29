#pragma once
// camera.exposure_s 0: the shutter a video camera's auto exposure takes for the plate. By day,
// without neutral-density filters, it shortens the shutter against the light: about 1/600 s.
// That is what `pluvia match` finds on three real daytime rain clips (NTURain ra1 1/622 s,
// NTURain rb2 1/389 s, Pexels' heavy rain 1/861 s: geometric mean 1/595 s), and what the base
// preset's f/4 takes at base ISO under an overcast sky (EV100 13: 1/512 s). At night
// it opens to the 180-degree shutter, half the frame time (1/50 s at 25 fps), where drops far
// from the lamps fade into the dark and those near them draw long glints.
#include "pipeline/camera_settings.h"
#include "pipeline/stage.h"

namespace pluvia {

inline constexpr double kDaylightExposureSeconds = 1.0 / 600.0;

// Sets camera.autoExposureSeconds from the plate's metadata (ExposureTime, when its files state
// it), else from the clip's still (stages/plate_lights.h: a night plate)
// when the camera leaves its exposure to auto; logs it once per stage.
void resolveAutoExposure(CameraSettings& camera, ClipContext& clip, const char* stage);

}  // namespace pluvia
