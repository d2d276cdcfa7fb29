#pragma once
// Checks and preparation of render inputs shared by RainRenderer and renderRainCpu, so both
// reject the same inputs and compare against the same depths.
#include <cfloat>
#include <cmath>
#include <vector>

#include "image/image.h"
#include "rain/streak_types.h"

namespace pluvia::gpu {

// Stands in for "infinitely far" (no depth plane, +inf, NaN): a finite value keeps the
// streak-behind-scene comparison well defined on every GPU (some flush infinities in textures).
inline constexpr float kFarDepthMeters = 3.0e38f;

// The scene depth a streak is compared with: as comparableSceneDepth(), every non-finite value
// (sky, NaN) is kFarDepthMeters.
inline float comparableDepthMeters(float depthMeters) {
  return std::abs(depthMeters) <= FLT_MAX ? depthMeters : kFarDepthMeters;
}

// Throw pluvia::Error (stage "rain") naming what is wrong.
void validateFrame(const Image& frame);
void validateShading(const rain::ShadingParams& shading);
void validateAtlas(const rain::StrokeAtlas& atlas);
void validateStreaks(const std::vector<rain::StreakInstance>& streaks, int strokeCount);

// The frame's "depth" plane with every non-finite or missing value replaced by kFarDepthMeters.
void comparableSceneDepth(const Image& frame, std::vector<float>& depthMeters);

// Sets "rain.R", "rain.G", "rain.B", "rain.A" and "matte" from an interleaved premultiplied
// RGBA rain layer of frame.pixelCount() pixels.
void storeRainLayer(const std::vector<float>& rainRgba, Image& frame);

// Finishes Eq. 2 of rain_renderer.h from the layer of the streaks' own radiance, L = (rgb, A):
// the premultiplied over-composite of alpha_i * C_i, read back from the GPU. Since C' = C + c*B
// with one B per pixel and sum_i alpha_i * prod_{j>i} (1 - alpha_j) = A, the rain layer is
// L.rgb + c * B * A and the composite is rain + (1 - A) * B: the same maths as blending C'
// streak by streak, in a different order. Sets frame.rgba's RGB (its alpha is kept) and the
// planes "rain.R", "rain.G", "rain.B", "rain.A" and "matte"; pixels with no rain keep B.
void compositeRainLayer(const std::vector<float>& radianceLayer, float backgroundWeight,
                        Image& frame);

// A frame's composite and rain planes, as pointers (planes created when absent).
struct RainPlanes {
  float* rgba;
  float* r;
  float* g;
  float* b;
  float* a;
  float* matte;
};
RainPlanes rainPlanesOf(Image& frame);

// The same as compositeRainLayer for pixels [first, first + count) of a layer already in the
// planes "rain.R", "rain.G", "rain.B", "rain.A" (the CPU rasteriser draws there): adds
// c * B * A to the rain planes, composites rgba and sets matte = A.
void compositeRainPixels(float backgroundWeight, const RainPlanes& planes, size_t first,
                         size_t count);

// Sets the rain planes to zero: the result when no streak is drawn.
void clearRainLayer(Image& frame);

}  // namespace pluvia::gpu
