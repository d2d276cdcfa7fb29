#pragma once
// The preset's local lights placed in one frame's camera space, for the lights stage (halos and
// beams: optics/light_halos.h), the rain stage (lit drops: optics/drop_local_light.h) and the
// glare stage.
#include <vector>

#include "geometry/camera.h"
#include "optics/local_light.h"
#include "stages/lights_settings.h"

namespace pluvia {

// The lights of `settings` at `frame`, in the camera space of `camera` (world-frame lights
// transformed, spot axes normalised). Throws pluvia::Error naming the light (lights.list[i])
// when a spot's axis is zero.
std::vector<optics::LocalLight> lightsAtFrame(const LightsSettings& settings, const Camera& camera,
                                              double frame);

}  // namespace pluvia
