#pragma once
// The skylight fog model over a frame (optics/skylight_scattering.h): per pixel with a finite
// depth, L = L_in(view) (1 - exp(-sigma d)) + plate exp(-sigma d), d the path to the surface
// (the depth plane holds z-depth; the path along the pixel's ray is longer), never longer than
// maxPathMeters (the rain's visibility). Pixels of infinite depth, the sky, keep their values.
// L_in is smooth over the picture (the table's texels span degrees, a pixel hundredths of one):
// it is looked up at nodes skylightNodeStepPx apart and interpolated bilinearly between them
// (within 2e-3 of a lookup per pixel: tests/stages/test_skylight_fog.cpp); a small picture or
// a wide lens looks up every pixel.
#include "geometry/camera.h"
#include "image/image.h"
#include "optics/skylight_scattering.h"

namespace pluvia {

// Node spacing in pixels: an eighth of a table texel at the frame's centre, 1 to 16.
int skylightNodeStepPx(const Camera& camera, const optics::SkylightTable& table);

void applySkylightFog(Image& image, const Camera& camera, const optics::SkylightTable& table,
                      const optics::SkylightMedium& medium, double maxPathMeters);

}  // namespace pluvia
