#pragma once
// The data the rain simulation hands to a renderer (gpu::RainRenderer, or its CPU twin
// gpu::renderRainCpu): streaks, the stroke mattes they are textured with, and the shading
// inputs. Plain CPU types: nothing here needs a GPU. The maths they feed is written out in
// gpu/rain_renderer.h.
#include <array>
#include <cmath>
#include <vector>

#include "image/equirect.h"

namespace pluvia::rain {

// One streak, 16 floats (laid out for the shaders' streak storage buffer, std430).
struct StreakInstance {
  float headX, headY, tailX, tailY;  // pixels; origin at the top-left corner, y down
  float widthPx, alpha, depthMeters, strokeIndex;
  float viewX, viewY, viewZ;  // unit direction camera -> drop (world space)
  // The drop's oscillation (Garg and Nayar 2006): the local lights' glint is beaded along the
  // streak with beadCycles periods over its length (v from 0 to 1), starting at beadPhase
  // (in periods). See localLightBead().
  float beadCycles;
  // Radiance the local lights add to the drop (scene-linear); zero, and the bead's phase, for a
  // population built without lights (benches, tests) that leaves them out of its initialiser.
  float localR = 0.0f, localG = 0.0f, localB = 0.0f;
  float beadPhase = 0.0f;
};
static_assert(sizeof(StreakInstance) == 16 * sizeof(float));

// How deep the beads are: the local-light term is scaled by 1 +/- kBeadDepth.
inline constexpr float kBeadDepth = 0.5f;

// The bead factor at matte coordinate v: 1 + kBeadDepth * (2 g - 1) with g = 4 f (1 - f) and
// f = fract(phase + cycles * v), a parabolic stand-in for (1 - cos 2 pi f) / 2 (within 0.06),
// chosen because every backend (GLSL, AVX2, plain C++) evaluates it with the same few
// operations. Its mean over a period is 1 + kBeadDepth / 3 (the cosine's would be 1).
inline float localLightBead(float cycles, float phase, float v) {
  const float x = phase + cycles * v;
  const float f = x - std::floor(x);
  const float g = 4.0f * f * (1.0f - f);
  return 1.0f + kBeadDepth * (2.0f * g - 1.0f);
}

// The quad of a streak: it spans from head to tail along its axis, extended by widthPx / 2 at
// both ends, and widthPx across. Matte coordinates: u across (0 left edge .. 1 right edge when
// looking from head to tail), v along (0 at head end .. 1 at tail end).

// Stroke mattes packed in one single-channel float atlas.
struct StrokeAtlas {
  int width = 0;
  int height = 0;
  std::vector<float> alpha;                 // width * height, row 0 at the top
  std::vector<std::array<float, 4>> rects;  // per stroke: x0, y0, x1, y1 in atlas pixels
};

// Shading inputs: the two terms of C (gpu/rain_renderer.h), at least one of them present, and
// c. SH term: real SH of order L = shOrder <= 3 ((L+1)^2 coefficients, index l*l + l + m), basis
// as in shaders/common_sh.glsl and its CPU twin shEvaluate(); used only when envSh is non-empty.
// Map term: per view direction, the radiance a drop shows (the environment already convolved
// with the drop's transfer); used only when radianceMap is non-empty. A map is meant to be
// small (128 x 64, say) and to change per clip, not per frame: RainRenderer::render() compares
// it with the one on the GPU and uploads it only when it differs.
struct ShadingParams {
  int shOrder = 0;
  std::vector<std::array<float, 3>> envSh;  // (shOrder+1)^2 RGB coefficients; empty: no SH term
  std::vector<float> transferZonal;         // shOrder+1 values: rotated zonal transfer (see above)
  EquirectMap radianceMap;                  // empty: no map term
  float backgroundWeight = 0.0f;            // c in C' = C + c*B
};

// Evaluates the real SH basis up to order 3 at unit direction (x, y, z): 16 values.
std::array<float, 16> shEvaluate(float x, float y, float z);

}  // namespace pluvia::rain
