#pragma once
// The skylight fog model over a frame (optics/skylight_scattering.h): per pixel with a finite
// depth, L = L_in(view) (1 - exp(-sigma d)) + plate exp(-sigma d), d the path to the surface
// (the depth plane holds z-depth; the path along the pixel's ray is longer), never longer than
// maxPathMeters (the rain's visibility). Pixels of infinite depth, the sky, keep their values.
#include "geometry/camera.h"
#include "image/image.h"
#include "optics/skylight_scattering.h"

namespace pluvia {

void applySkylightFog(Image& image, const Camera& camera, const optics::SkylightTable& table,
                      const optics::SkylightMedium& medium, double maxPathMeters);

}  // namespace pluvia
