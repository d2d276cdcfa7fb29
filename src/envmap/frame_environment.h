#pragma once
// The environment a plate shows of itself, for lighting the drops when nothing better is given
// (lighting.source "frame", the default). A drop refracts light from a cone of about 165 deg
// around the view (Garg and Nayar), mostly the sky above and the scene around: lighting it with
// the frame's average, which a uniform environment is, makes it invisible (the transfer function
// integrates to about 1: the furnace test), which is why rain looked too faint before.
// The map: inside the camera's field of view, the frame itself; elsewhere, the frame's mean
// radiance at the same elevation (its rows seen at that height above or below the horizon),
// the bottom rows' mean below the frame; above the frame, the sky: the mean of the frame's own
// sky where it shows one, else the CIE overcast sky (L = Lz (1 + 2 cos theta) / 3, Huang et
// al.) that lights the scene as brightly as the frame shows it, taking a typical albedo of 0.18
// (neutral grey).
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
  std::array<float, 3> horizonRgb{0, 0, 0};  // the sky at the horizon: the airlight
};

// `sky`: width * height, 1 where the frame shows sky (empty: none known).
FrameEnvironment frameEnvironment(const Image& frame, const Camera& camera,
                                  const std::vector<uint8_t>& sky, int widthTexels = 128);

}  // namespace pluvia::envmap
