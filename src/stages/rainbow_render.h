#pragma once
// The rainbow added to a frame: per pixel, the sun's light scattered back by terms 3 and 4 of
// the drops (optics/rainbow.h) along the ray through the rain, single scattering:
//   L_c = E_c D_c(theta) (sigma_rain / 2) / sigma_t (1 - exp(-sigma_t s)),
// theta the angle between the view ray and the sun's direction (180 deg: looking at the
// antisolar point), sigma_rain / 2 the drops' geometric cross-section per metre (their
// extinction counts twice it, the diffracted half going forward, not into the bow), sigma_t the
// extinction by rain and fog, and s the path: the distance to the scene (depth plane, z-depth
// converted along the ray), or the shower's extent for the sky. Nearer scene depth thus hides
// the bow's far rain. The sun's beam is taken as unattenuated.
#include <array>
#include <string>

#include "geometry/camera.h"
#include "image/image.h"
#include "optics/rainbow.h"
#include "stages/sun.h"

namespace pluvia {

struct RainbowVolume {
  double rainExtinctionPerMeter = 0.0;  // rain::rainExtinctionPerMeter of the rate
  double fogExtinctionPerMeter = 0.0;
  double showerExtentMeters = 2000.0;
  double strength = 1.0;
};

// Adds the bows to `image` (reads its "depth" plane when present; absent: every ray meets only
// sky). Writes nothing where the sun is below the horizon.
void addRainbow(Image& image, const Camera& camera, const Sun& sun,
                const std::array<optics::RainbowProfile, 3>& profiles, const RainbowVolume& volume);

// Why `camera` cannot show a bow of this sun ("" when it can): the sun below the horizon, or
// no pixel direction within 38..56 deg of the antisolar point (where the bows and their
// smoothing lie).
std::string rainbowHiddenReason(const Camera& camera, const Eigen::Vector3d& sunDirection);

}  // namespace pluvia
