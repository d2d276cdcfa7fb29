#pragma once
// The rings of rain/ripples.h on a frame: each alive ring's slope added into the water surface's
// per-pixel gradient (dh/dx, dh/dz, world), then the surface shaded as a mirror of the
// environment: a tilted normal n' turns the reflected ray from r0 to r' and Fresnel's
// reflectance from R0 to R', so the pixel changes by R' L(r') - R0 L(r0) (the plate already
// holds the level water's own R0 L(r0)). The water is level (+Y up) where the mask says so.
// Crests are drawn where a pixel spans at most half their packet (rippleReachMeters): beyond,
// they would alias.
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "image/image.h"
#include "rain/ripples.h"

namespace pluvia::rain {

// The farthest z-depth at which a ring's crests are resolved by `camera`.
double rippleReachMeters(const Camera& camera);

// Adds the slopes of `rings` (impacts, at `timeSeconds`) over the pixels where `water` is
// non-zero (width * height) into slopeX and slopeZ (width * height, world dh/dx and dh/dz).
// `depth`: the frame's z-depths, metres.
void addRippleSlopes(const Camera& camera, const std::vector<float>& depth,
                     const std::vector<uint8_t>& water, const std::vector<const Impact*>& rings,
                     double timeSeconds, std::vector<float>& slopeX, std::vector<float>& slopeZ);

using EnvironmentLookup = std::function<std::array<float, 3>(const Eigen::Vector3d& direction)>;

// The water shaded as a mirror where a slope is non-zero (keeping it non-negative).
//  - `environment` gives L along a world direction: the pixel changes by R' L(r') - R0 L(r0).
//  - With `plate` (the frame before the rings) and its `water` mask, the water mirrors the plate's
//    own reflection instead wherever it shows the tilted ray's: the level water at pixel q shows
//    the scene along r0(q), so the pixel whose view ray is r' mirrored in the level (q: r0(q) =
//    r') holds L(r') R0(q), its light from below taken as none (a puddle over dark ground); the
//    pixel becomes (R' / R0(q)) plate(q), the plate's trees, sky and lamps displaced by the ring
//    as in real puddles. Where q falls off the frame or off the water, the environment's L.
void shadeRippleMirror(Image& image, const Camera& camera, const std::vector<float>& depth,
                       const std::vector<float>& slopeX, const std::vector<float>& slopeZ,
                       const EnvironmentLookup& environment, const Image* plate = nullptr,
                       const std::vector<uint8_t>* water = nullptr);

}  // namespace pluvia::rain
