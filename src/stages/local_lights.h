#pragma once
// The local lights of one frame, for the lights stage (halos and beams) and the rain stage (lit
// drops): the preset's lights placed in the frame's camera space, the glow they add to a frame
// by single scattering (optics/single_scattering.h), and the radiance they give one drop
// through its transfer function (optics/drop_transfer.h).
#include <array>
#include <vector>

#include "geometry/camera.h"
#include "image/image.h"
#include "optics/drop_transfer.h"
#include "optics/single_scattering.h"
#include "pipeline/stage.h"
#include "stages/lights_settings.h"

namespace pluvia {

// The lights of `settings` at `frame`, in the camera space of `camera` (world-frame lights
// transformed, spot axes normalised). Throws pluvia::Error naming the light (lights.list[i])
// when a spot's axis is zero.
std::vector<FrameLight> lightsAtFrame(const LightsSettings& settings, const Camera& camera,
                                      double frame);

optics::LocalLight localLight(const FrameLight& light);

struct HaloResult {
  int culled = 0;        // lights with no tile above the threshold
  size_t pixelsLit = 0;  // evaluations of the single-scattering integral done
};

// Adds every light's in-scattered radiance to image.rgba and, when the image has the plane
// "lights.R", to the planes "lights.R".."B" ("lights.A" made and left 0): per pixel, the ray
// through its centre up to the scene there (the "depth" plane's z-depth; none or +inf: the sky, an
// infinite ray). Each light is evaluated on a grid of 16 px tiles' corner pixels (found coarse to
// fine: bilinear over cells of 8, 4 and 2 tiles where its glow turns slowly, away from its image
// and depth edges), and a tile is then
//  - skipped for a light when its and its 8 neighbours' corners are all below `thresholdRadiance`
//    divided by the number of lights (at a depth edge, the corners' unoccluded glow; a beam
//    narrower than a tile passing between all the corners of three tiles in a row is missed),
//    and a light with no corner above `thresholdRadiance` is culled;
//  - interpolated from its corners when the scene in it is one smooth surface (1/z bilinear to
//    5 %) and its corners glow within 25 % of each other or differ by under 1 % of all the
//    lights' glow there: the lights' corners are summed per tile and interpolated once per frame;
//  - at a depth edge where the glow turns slowly, interpolated from its corners' glow at a few
//    ray lengths spanning its depths (5 % apart), in log depth per pixel;
//  - on 4 px sub-tiles treated alike where the glow turns fast and around the light's own image,
//    every pixel within 8 px of that image.
// `everyPixel`: every lit pixel evaluated (the reference the interpolation is measured against).
HaloResult addHalos(Image& image, const Camera& camera, const std::vector<FrameLight>& lights,
                    double betaPerMeter, const optics::ScatteringTables& tables,
                    double thresholdRadiance, bool everyPixel = false);

// The radiance the lights give one drop, and the unit direction from the drop to the light that
// gives it most (camera space; zero when none lights it).
struct DropLocalLight {
  std::array<float, 3> rgb{0, 0, 0};
  std::array<double, 3> towardsBrightest{0, 0, 0};
};

// The radiance the lights give a drop at `dropMeters` (camera space) seen along unit `view`
// (camera -> drop): sum over lights of D(angle(view, drop -> light)) * I(theta) rgb / d^2 *
// exp(-beta d), d the distance from the drop to the light, at least the bulb's radius.
DropLocalLight dropLocalRadiance(const optics::TransferTable& transfer,
                                 const std::vector<FrameLight>& lights, double betaPerMeter,
                                 const std::array<double, 3>& dropMeters,
                                 const std::array<double, 3>& view);

// The spot's I(theta) / I0 at cos(theta) (1 for a point light): Huang et al.'s
// (1 - q)(cos theta - cos A) / (1 - cos A) + q inside the cone, 0 outside.
double spotFactor(const FrameLight& light, double cosTheta);

}  // namespace pluvia
