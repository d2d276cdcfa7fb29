#pragma once
// Manual depth layers (Wang et al. section 5: depth assigned by hand when there is no parallax).
// Layers are painted in list order, each over the pixels it covers; pixels no layer covers are
// sky, at +infinity. Depth is z-depth in metres along the optical axis.
//   {"type": "ground"}                                  the plane y = 0 under the camera
//   {"type": "card", "distance_m": 40, "x0": 0, "x1": 1, "y0": 0, "y1": 0.2}
//                                                      a vertical card facing the camera over the
//                                                      image rectangle (fractions of width/height)
//   {"type": "sky", "x0": 0, "x1": 1, "y0": 0, "y1": 0.1}  forces +infinity over the rectangle
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/camera.h"

namespace pluvia {

// Returns width * height z-depths (metres, +inf for sky). Throws pluvia::Error naming the layer
// index on an unknown type (the preset validator normally catches it first).
std::vector<float> rasterizeDepthLayers(const Camera& camera, const nlohmann::json& layers);

}  // namespace pluvia
