#pragma once
// Manual depth layers (Wang et al. section 5: depth assigned by hand when there is no parallax).
// Layers are painted in list order, each over the pixels it covers; pixels no layer covers are
// sky, at +infinity. Depth is z-depth in metres along the optical axis. Image positions are
// fractions of the width/height, (0, 0) the top-left corner.
//   {"type": "ground"}                                  the plane y = 0 under the camera (follows
//                                                      the camera of the frame: height and tilt)
//   {"type": "card", "distance_m": 40, "x0": 0, "x1": 1, "y0": 0, "y1": 0.2}
//                                                      a vertical card facing the camera over the
//                                                      image rectangle
//   {"type": "polygon", "points": [[x, y], ...], "depth_m": 12, "depth_bottom_m": 4}
//                                                      a polygon (3 or more points) at depth_m, or,
//                                                      with depth_bottom_m, a depth that goes
//                                                      linearly (in depth, per image row) from
//                                                      depth_m at its topmost point to
//                                                      depth_bottom_m at its lowest (a receding
//                                                      road or wall)
//   {"type": "sky", "x0": 0, "x1": 1, "y0": 0, "y1": 0.1}  forces +infinity over the rectangle,
//   {"type": "sky", "points": [[x, y], ...]}               or over the polygon (points win)
//
// Polygons fill by the even-odd rule at pixel centres: a pixel is inside when its centre is;
// a centre exactly on a left edge is inside, on a right edge outside (so abutting polygons share
// no pixel and leave no gap).
//
// Over frames: every number above (distance_m, depth_m, depth_bottom_m, x0..y1) may be keyframes
// (preset/ramp.h: {"keys": [[frame, value], ...], "interpolation": ...} or [[frame, value], ...]).
// "points" may be keyframed as a list of {"frame": F, "points": [[x, y], ...]} in strictly
// increasing frame order, each with the same number of points: positions interpolate linearly
// between keys and hold before the first and after the last.
#include <functional>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/camera.h"

namespace pluvia {

// Evaluates a keyframed number at a frame. Geometry does not link the presets, which own the
// keyframe format (preset/ramp.h): callers pass
//   [](const nlohmann::json& v, double f) { return Ramp::fromJson(v).valueAt(f); }
using KeyedNumberAt = std::function<double(const nlohmann::json& value, double frame)>;

// Returns width * height z-depths (metres, +inf for sky) at clip frame `frame`, with the layers'
// fields evaluated at that frame and `camera` the camera of that frame. Without `numberAt` only
// plain numbers are accepted. Throws pluvia::Error naming the layer index (and frame) on an
// unknown type, a keyframed field without `numberAt`, or a polygon of fewer than 3 points (the
// preset validator normally catches these first).
std::vector<float> rasterizeDepthLayers(const Camera& camera, const nlohmann::json& layers,
                                        double frame = 0.0, const KeyedNumberAt& numberAt = {});

// True when some layer changes over frames: a number given as two or more keys of different
// values, or points given as two or more different keys. A ground layer also changes with a
// moving camera, which the caller knows about (CameraPath::moving()).
bool depthLayersAnimated(const nlohmann::json& layers);

// True when a layer is the ground plane under the camera (it moves with a moving camera).
bool depthLayersHaveGround(const nlohmann::json& layers);

}  // namespace pluvia
