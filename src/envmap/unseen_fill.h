#pragma once
// The directions of a stitched panorama that no frame saw (panorama.h, UnseenFill): the nearest
// seen colour, or a sky model and a ground model fitted to what was seen.
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "envmap/sky_model.h"
#include "image/equirect.h"

namespace pluvia::envmap {

// Per texel (index y * width + x), the index of the nearest seen texel in texel distance on the
// map wrapped in longitude; its own index where seen; -1 when nothing is seen.
std::vector<int> nearestSeenTexels(const cv::Mat& coverage);

// Each unseen texel takes its nearest seen texel's colour.
void fillNearest(EquirectMap& map, const cv::Mat& coverage, const std::vector<int>& nearest);

struct ModelFillSettings {
  std::optional<Vec3> sun;  // known sun direction (from the lights)
  // Over these angles from the nearest seen texel, an unseen texel goes from that texel's colour
  // (no seam) to the model's: the ratio seen / model there is applied, fading in log space.
  // Measured on the shared HDRs (pluvia report envmap): sky at the boundary 20°; the ground
  // and what stands in front of the sky at the boundary (a building, a tree) 60°.
  double skyBlendDeg = 20.0;
  double obstacleBlendDeg = 60.0;
};

// UnseenFill::SkyModel: the sky (elevation > 0) from fitSky on the seen sky: smooth, unclipped
// texels above the horizon, the bright envelope of what is seen there (what stands in front of
// the sky is darker than it). The ground a Lambertian surface of the seen ground's albedo under
// that sky: the mean radiance of the seen ground at the coverage's lower edge (with no ground
// seen, albedo 0.125 under the fitted sky). With no sky seen, the CIE overcast sky that gives the
// seen ground at albedo 0.125 (envmap/scene_albedo.h). `clipped`: CV_8UC1, nonzero where a seen
// texel is only a lower bound or a light (left out of the fit). Returns false, doing nothing, when
// nothing is seen or when more of the seen sky is clipped than could be fitted (a bright sky
// through leaves: what is left unclipped is not that sky); `model` then says why. `model` says what
// was fitted.
bool fillModel(EquirectMap& map, const cv::Mat& coverage, const cv::Mat& clipped,
               const std::vector<int>& nearest, const ModelFillSettings& settings,
               std::string& model);

}  // namespace pluvia::envmap
