#pragma once
// `pluvia report lights`, the rows of whole frames: the lights stage's tiled halos
// (optics/light_halos.h: addHalos) against evaluating every pixel, on a synthetic street (sky,
// ground, a wall) with 10 and 100 lights.
#include "lab/lights_report.h"

namespace pluvia::lab {

// Appends a "halo frame" row per light count (mean and largest relative error per pixel and
// channel where the reference is at least a tenth of the threshold; time per pixel of a frame)
// and its every-pixel reference row.
void addHaloFrameRows(LightsReport& report, bool quick);

}  // namespace pluvia::lab
