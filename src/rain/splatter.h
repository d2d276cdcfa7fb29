#pragma once
// Splatter flashes (Wang et al. 2006, section 5, "Rain Splatter"): where a drop strikes a
// surface, a splatter texture lies flat on it for a short flash. Wang et al.'s splatters were
// drawn by an artist, their size and number growing with the rain; here the texture is made per
// impact from its key (deterministic), sized by the drop's diameter D, and as many as the
// impacts (the drop flux, splash_rate.h): a core disc of radius 1.2 D and 5 to 8 rays of width
// 0.4 D reaching 2.5 to 4 D, each with a droplet of radius 0.3 D beyond its tip, all on the
// horizontal plane through the impact point, kSplatterPeakOpacity opaque (a thin film of water).
// It shows from the impact for `flashSeconds`; a frame's shutter [open, close] sees it with the
// share of the exposure the flash overlaps.
//
// A splatter is drawn per pixel through the pixel's own surface point (from the depth plane):
// only where that point lies on the horizontal plane through the impact (within
// kSurfaceToleranceMeters or 1 % of the depth) and inside the texture, so only on the surface
// that took the impact and never over what stands in front of it.
#include <array>
#include <vector>

#include "geometry/camera.h"
#include "image/image.h"
#include "rain/splashes.h"

namespace pluvia::rain {

inline constexpr double kSplatterReachPerDiameter = 5.0;  // beyond the farthest droplet, in D
inline constexpr double kSplatterPeakOpacity = 0.6;

// The texture's opacity, 0 to kSplatterPeakOpacity, at (u, v) metres from the impact point along
// world X and Z, its edges smoothed over `blurMeters` (a pixel's footprint).
double splatterOpacity(const Impact& impact, double u, double v, double blurMeters);

// The share of [openSeconds, closeSeconds] that the flash [impact, impact + flashSeconds]
// covers: 0 when they do not meet.
double splatterExposureShare(double impactSeconds, double flashSeconds, double openSeconds,
                             double closeSeconds);

struct ShadedImpact {
  const Impact* impact = nullptr;
  std::array<float, 3> radiance{0, 0, 0};
};

// Draws the splatters of `impacts` seen by the shutter over `image`, in their order, and adds
// their coverage to `alpha` (the splash AOV), scaled by `opacity`.
void drawSplatters(Image& image, std::vector<float>& alpha, const std::vector<float>& depth,
                   const Camera& camera, const std::vector<ShadedImpact>& impacts,
                   double flashSeconds, double openSeconds, double closeSeconds, float opacity);

}  // namespace pluvia::rain
