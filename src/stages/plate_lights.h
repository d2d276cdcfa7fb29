#pragma once
// Lights found in the plate (lights.find): the lamps of a night plate show as clipped blobs.
// Each blob becomes a point light where the plate's lamp is: its centroid's ray, at the depth
// the depth stage gives around it, coloured like the unclipped rim around it.
#include <vector>

#include "geometry/camera.h"
#include "image/image.h"
#include "pipeline/stage.h"
#include "stages/lights_settings.h"

namespace pluvia {

// A clipped blob of the still, in pixels (x right, y down, pixel centres at +0.5).
struct PlateBlob {
  double xPx = 0.0, yPx = 0.0;  // centroid
  int areaPx = 0;
  std::array<double, 3> rgb{1, 1, 1};  // rim chromaticity, max channel 1
  std::vector<int> rimPixels;          // y * width + x of the ring just outside the blob
  double rimLuminance = 0.0;           // the ring's mean luminance (Rec. 709 weights)
  // The mean luminance of a ring farther out, from 2 to 4 times the blob's radius (8 to 16 px
  // at least): where a lamp's own glow has faded and a lit wall is still bright.
  double surroundLuminance = 0.0;
};

// How bright a plate is: its luminance (Rec. 709 weights, working space) at two quantiles, lamps'
// glows left out (a clipped core's bright surround that stays within a few of its radii).
struct PlateLuminance {
  double median = 0.0;      // how dark the plate is
  double upperTenth = 0.0;  // the 90th percentile: how bright its brightest tenth is
};
PlateLuminance plateLuminance(const Image& still);

// How much of each pixel of a night plate's `image` (width * height, 0..1) is a lamp: 1 on the
// clipped cores inside their own glows and on those glows (the bright pixels joined to a core
// that fade away from it, as plateLuminance leaves them out), and within the radius where the
// glow's ring luminance has lost nine tenths of its excess over the scene around; falling to 0
// over kLampFeatherPx outside the mask and over as far again as that radius outside it, so that
// what is kept has no edge.
// Found at most kLampShareWidthPx wide (a wider image at a whole fraction of its size: 1080p
// took 60 ms a frame at its own), so the feather is that many px of the smaller image.
inline constexpr double kLampFeatherPx = 8.0;
inline constexpr int kLampShareWidthPx = 960;
std::vector<float> lampShare(const Image& image);

// A night plate: its median luminance under kNightMedianLuminance and nine tenths of it under
// kNightUpperLuminance (a shaded day plate is as dark at its median, but its sunlit tenth is not).
bool isNightPlate(const PlateLuminance& luminance);

// The blobs of `still` whose max channel is >= clipLevel (working-space units; the white of a
// display-referred file is 1.0) with at least minAreaPx pixels. The rim is the ring 1..4 px
// outside the blob; its colour is the mean of its pixels with no channel at clipLevel (white
// when every rim pixel is clipped).
std::vector<PlateBlob> findClippedBlobs(const Image& still, double clipLevel, int minAreaPx);

// The blob as a point light in world space (the camera's world: lightsAtFrame follows a moving
// camera past it). Distance: the median z-depth of the rim pixels in `depth` (width * height,
// z-depth in metres; +inf is sky), or backdropMeters when no rim pixel has a finite depth or
// `depth` is null. Radiant intensity: coreGain * clipLevel * Omega * d^2, the blob's solid angle
// Omega, its distance d, the clip level times coreGain its radiance; radius: the blob's.
FoundLamp plateLamp(const PlateBlob& blob, const Camera& camera, const std::vector<float>* depth,
                    double backdropMeters, double clipLevel, double coreGain);

// The found lamp as lights.list would give it: a world-frame point light.
LightSpec foundLampLight(const FoundLamp& lamp);

// lights.find on the clip's still: nothing when the plate is not a night one (isNightPlate)
// unless settings.findOnDayPlates; otherwise the
// clipped blobs in the dark (at most kMaxLampShareOfFrame of the frame, their rim under
// kLampRimOverClip of the clip level), placed by plateLamp with `camera` (the clip's first
// frame's) and `depth` (its depth; null: backdropMeters). A blob whose rim is bright is a lamp
// too when its surround is dark (under half that limit): a clipped core inside its own glow, as
// a street lamp or a headlight films at night. Logs what it looked for and found.
std::vector<FoundLamp> findPlateLamps(const Image& still, const LightsSettings& settings,
                                      const Camera& camera, const std::vector<float>* depth,
                                      double backdropMeters);

}  // namespace pluvia
