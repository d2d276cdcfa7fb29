#pragma once
// Splash particles drawn on the CPU: each particle's motion over the shutter as a capsule
// (a segment with round ends) of the particle's projected radius, at least half a pixel, with
// the opacity of motion blur: a particle of projected diameter d_px swept over L_px covers a
// pixel on its path for d / (L + d) of the shutter, and one smaller than a pixel covers
// (d_px)^2 of it. Depth-tested against the frame's depth plane (a particle behind the surface
// at its pixel is hidden; one on the surface is kept within kSurfaceToleranceMeters or 1 %),
// composited over the image with the given radiance, and its coverage accumulated in `alpha`.
#include <array>
#include <cstdint>
#include <vector>

#include "geometry/camera.h"
#include "image/image.h"
#include "rain/splashes.h"

namespace pluvia::rain {

inline constexpr double kSurfaceToleranceMeters = 0.05;
// Level of detail: a particle that covers no pixel by more than this (under a 10-bit code value
// over white) is not drawn. At 1080p that is most droplets of drops under 2 mm beyond a few
// metres: half the particles of a level camera's ground, and particles so sparse (about one in
// four pixels) that together they would add a few of these at most.
inline constexpr float kMinParticleCoverage = 1.0f / 1024.0f;
// Faint particles are thinned (stochastic pruning, Cook et al. 2007): one that covers a pixel by
// at most this is kept with probability coverage / kThinnedCoverage, chosen by its key, and
// drawn with kThinnedCoverage, so the expected coverage is unchanged while far fewer are drawn
// (`pluvia bench --day`: 84k particles a frame down to 59k). A kept one adds under an 8-bit
// code value.
inline constexpr float kThinnedCoverage = 1.0f / 256.0f;

struct ShadedParticle {
  SplashParticle particle;
  std::array<float, 3> radiance{0, 0, 0};
};

// A particle projected into the picture with its radiance: what drawProjectedParticles draws.
struct ProjectedParticle {
  float ax, ay, az, bx, by, bz;  // the segment's ends: pixels and z-depths (metres)
  float radius, alpha;           // pixels; coverage with the opacity of motion blur
  float inverseLengthSquared;    // 1 / (segment length in pixels)^2; 0 for a still particle
  int x0, x1, y0, y1;            // the pixels whose centres lie within radius + 0.5 of the segment
  std::array<float, 3> radiance;
};

// Projects `particle`. False (not drawn) when it is behind the camera, covers no pixel by
// kMinParticleCoverage (opacity included), is thinned out (`key`: the particle's own, the same
// in every render of its frame), or lies outside the frame.
bool projectSplashParticle(const Camera& camera, const SplashParticle& particle, float opacity,
                           const std::array<float, 3>& radiance, uint64_t key,
                           ProjectedParticle& out);

// Draws `groups` (each in its order, the groups in theirs) over the image. `depth`: width *
// height z-depths; `alpha`: width * height, the splash AOV (over-composited).
void drawProjectedParticles(Image& image, std::vector<float>& alpha,
                            const std::vector<float>& depth, int width, int height,
                            const std::vector<std::vector<ProjectedParticle>>& groups);

// projectSplashParticle (each particle's key: its index) and drawProjectedParticles over one
// list.
void drawSplashParticles(Image& image, std::vector<float>& alpha, const std::vector<float>& depth,
                         const Camera& camera, const std::vector<ShadedParticle>& particles,
                         float opacity);

}  // namespace pluvia::rain
