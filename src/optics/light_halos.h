#pragma once
// The halos and beams of a frame's local lights: the glow each adds to every pixel by single
// scattering in the rain and fog (optics/single_scattering.h), evaluated on tiles and
// interpolated where it turns slowly. The lights stage's renderer; `pluvia report lights`
// measures it against every pixel evaluated.
#include <cstddef>
#include <vector>

#include "geometry/camera.h"
#include "image/image.h"
#include "optics/local_light.h"
#include "optics/single_scattering.h"

namespace pluvia::optics {

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
HaloResult addHalos(Image& image, const Camera& camera, const std::vector<LocalLight>& lights,
                    double betaPerMeter, const ScatteringTables& tables, double thresholdRadiance,
                    bool everyPixel = false);

}  // namespace pluvia::optics
