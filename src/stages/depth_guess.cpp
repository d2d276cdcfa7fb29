#include "stages/depth_guess.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "sfm/sparse_densify.h"

namespace pluvia {
namespace {

// The sky is found at this longest side at most: the texture test works on a few pixels' scale
// either way, and a 4K plate would cost seconds for a mask that needs no such detail.
constexpr int kSkyMaxSidePx = 640;

}  // namespace

DepthGuess guessDepth(const Image& plate, const Camera& camera, double backdropMeters) {
  const int width = camera.width, height = camera.height;
  const double scale = std::min(1.0, double(kSkyMaxSidePx) / std::max(width, height));
  cv::Mat rgb = rgbMat(plate), small;
  cv::resize(rgb, small, cv::Size(), scale, scale, cv::INTER_AREA);
  cv::Mat bgr;
  cv::cvtColor(small, bgr, cv::COLOR_RGB2BGR);
  DensifyOptions options;
  options.groundCamera = camera;
  cv::Mat skySmall = estimateSkyMask(bgr, options), sky;
  cv::resize(skySmall, sky, cv::Size(width, height), 0, 0, cv::INTER_NEAREST);

  DepthGuess guess;
  guess.depthMeters.assign(size_t(width) * height, float(backdropMeters));
  const double heightMeters = camera.positionMeters.y();
  size_t skyCount = 0, groundCount = 0;
  for (int y = 0; y < height; ++y) {
    const uchar* s = sky.ptr<uchar>(y);
    for (int x = 0; x < width; ++x) {
      float& depth = guess.depthMeters[size_t(y) * width + x];
      if (s[x]) {
        depth = std::numeric_limits<float>::infinity();
        ++skyCount;
        continue;
      }
      // rayCamera has camera-space z = -1: its parameter at the ground is the z-depth.
      const Eigen::Vector3d ray = camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5);
      if (heightMeters > 0 && ray.y() < 0) {
        const double ground = heightMeters / -ray.y();
        if (ground < backdropMeters) {
          depth = float(ground);
          ++groundCount;
        }
      }
    }
  }
  guess.skyFraction = double(skyCount) / double(guess.depthMeters.size());
  guess.groundFraction = double(groundCount) / double(guess.depthMeters.size());
  return guess;
}

}  // namespace pluvia
