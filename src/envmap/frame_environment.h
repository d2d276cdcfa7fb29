#pragma once
// The environment a plate shows of itself, for lighting the drops when nothing better is given
// (lighting.source "frame", the default). A drop refracts light from a cone of about 165 deg
// around the view (Garg and Nayar), mostly the sky above and the scene around: lighting it with
// the frame's average, which a uniform environment is, makes it invisible (the transfer function
// integrates to about 1: the furnace test), which is why rain looked too faint before.
// The map: inside the camera's field of view, the frame itself; elsewhere, the frame's mean
// radiance at the same elevation (its rows seen at that height above or below the horizon),
// the top rows' mean above the frame and the bottom rows' below. The sky above the frame is at
// least as bright as the overcast sky that lights the scene as brightly as the frame shows it
// (the frame's mean luminance over a typical albedo of 0.25), keeping the top rows' colour.
#include "geometry/camera.h"
#include "image/equirect.h"
#include "image/image.h"

namespace pluvia::envmap {

// `frame` in the working space, seen by `camera` (the frame's size and pose).
EquirectMap frameEnvironment(const Image& frame, const Camera& camera, int widthTexels = 128);

}  // namespace pluvia::envmap
