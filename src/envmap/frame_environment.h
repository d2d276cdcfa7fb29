#pragma once
// The environment a plate shows of itself, for lighting the drops when nothing better is given
// (lighting.source "frame", the default). A drop refracts light from a cone of about 165 deg
// around the view (Garg and Nayar), mostly the sky above and the scene around: lighting it with
// the frame's average, which a uniform environment is, makes it invisible (the transfer function
// integrates to about 1: the furnace test), which is why rain looked too faint before.
// The map: inside the camera's field of view, the frame itself; elsewhere, the frame's mean
// radiance at the same elevation (its rows seen at that height above or below the horizon);
// above the frame, the sky: the CIE overcast sky (L = Lz (1 + 2 cos theta) / 3, Huang et al.),
// brightening from the horizon to the zenith: the brighter of the one through the frame's own sky
// where it shows one and the one that lights the scene (mostly upright surfaces of the metered
// albedo, 0.125: envmap/scene_albedo.h) as brightly as the frame shows it, the frame's own sky
// pixels lifted onto it where they are darker (clipped); below the frame (by day), wet level
// ground under that sky, reached from the frame's lowest row. A clear (blue) sky in the plate is
// measured, not clipped: the sky above is the CIE profile through it, and the ground below is lit
// as the scene is.
#include <array>
#include <cstdint>
#include <vector>

#include "geometry/camera.h"
#include "image/equirect.h"
#include "image/image.h"

namespace pluvia::envmap {

// `frame` in the working space, seen by `camera` (the frame's size and pose).
struct FrameEnvironment {
  EquirectMap radiance;
  // The airlight: the frame's own sky where it shows one, else the sky at the horizon.
  std::array<float, 3> horizonRgb{0, 0, 0};
  // The overcast sky assumed above the frame: its zenith luminance, and whether it goes through
  // the plate's own sky (else it is the one that lights the scene as the plate shows it).
  float zenithLuminance = 0.0f;
  bool skyFromPlate = false;
  // The plate shows a clear sky (blue): the sky above is its own, not lifted, and the ground
  // below is lit as the scene is (by the sun).
  bool clearSky = false;
};

// `sky`: width * height, 1 where the frame shows sky (empty: none known). A night plate is lit by
// its lamps, not by the sky: its sky is only what the plate shows of it (the frame's own sky, or
// its top rows carried up), with no overcast sky above.
FrameEnvironment frameEnvironment(const Image& frame, const Camera& camera,
                                  const std::vector<uint8_t>& sky, bool nightPlate,
                                  int widthTexels = 128);

}  // namespace pluvia::envmap
