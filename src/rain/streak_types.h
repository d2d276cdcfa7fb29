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

// One streak, 20 floats (laid out for the shaders' streak storage buffer, std430: five vec4).
struct StreakInstance {
  float headX, headY, tailX, tailY;  // pixels; origin at the top-left corner, y down
  float widthPx, alpha, depthMeters, strokeIndex;
  float viewX, viewY, viewZ;  // unit direction camera -> drop (world space)
  // The drop's oscillation (Garg and Nayar 2006): beadCycles periods of mode (2, 0) over the
  // exposure (v from 0 to 1 along the streak), starting at beadPhase periods. The local lights'
  // glint is beaded along the streak by it (localLightBead()).
  float beadCycles;
  // Radiance the local lights add to the drop (scene-linear); zero, and the bead's phase, for a
  // population built without lights (benches, tests) that leaves them out of its initialiser.
  float localR = 0.0f, localG = 0.0f, localB = 0.0f;
  float beadPhase = 0.0f;
  // The amplitudes of modes (2, 0) and (3, 1) in the log of the glint's brightness
  // (rain/drop_glint.h): the drop simulation writes the drop's own shape amplitudes A(2,0) and
  // A(3,1) cos(phi_rot), and the lights turn them into the glint's for the light that lights the
  // drop most (shapeGlint()). Zero: no beads.
  float glintMode20 = 0.0f, glintMode31 = 0.0f;
  float padding[2] = {0.0f, 0.0f};  // std430 rounds a streak up to whole vec4s
};
static_assert(sizeof(StreakInstance) == 20 * sizeof(float));

// omega3 / omega2 of Garg and Nayar's Eq. (2): sqrt(3 * 2 * 5 / (2 * 1 * 4)).
inline constexpr float kOscillationModeRatio = 1.93649167f;

// sin(2 pi s) by two parabolas, -4 y (1 - |y|) with y = 2 fract(s) - 1 (within 0.056 of it),
// chosen because every backend (GLSL, AVX2, plain C++) evaluates it with the same few exact
// operations.
inline float parabolicSine(float s) {
  const float y = 2.0f * (s - std::floor(s)) - 1.0f;
  return -4.0f * y * (1.0f - std::abs(y));
}

// The bead factor at matte coordinate v: a glint's brightness goes as 1 / K, K the Gaussian
// curvature of the drop's surface where it reflects the light, and the oscillating shape moves
// log K by x = glintMode20 sin(2 pi s) + glintMode31 sin(2 pi r s), s = phase + cycles * v, r =
// kOscillationModeRatio (both modes run from the same instant, Garg and Nayar's Eq. 1). exp(-x)
// is taken as exp(-asinh x) = sqrt(1 + x^2) - x: the same to second order in x, positive and
// finite for every x, and exact in every backend (no exp in AVX2); for x >= 0 it is evaluated as
// 1 / (sqrt(1 + x^2) + x), which does not cancel. 1 where both modes are 0.
inline float localLightBead(float cycles, float phase, float mode20, float mode31, float v) {
  const float s = phase + cycles * v;
  const float x = mode20 * parabolicSine(s) + mode31 * parabolicSine(kOscillationModeRatio * s);
  const float r = std::sqrt(1.0f + x * x) + std::abs(x);
  return x >= 0.0f ? 1.0f / r : r;
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
