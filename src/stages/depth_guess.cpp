#include "stages/depth_guess.h"

#include <limits>

namespace pluvia {

DepthGuess guessDepth(const std::vector<uint8_t>& sky, const Camera& camera,
                      double backdropMeters) {
  const int width = camera.width, height = camera.height;
  DepthGuess guess;
  guess.depthMeters.assign(size_t(width) * height, float(backdropMeters));
  const double heightMeters = camera.positionMeters.y();
  size_t skyCount = 0, groundCount = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * width + x;
      float& depth = guess.depthMeters[i];
      if (sky[i]) {
        depth = std::numeric_limits<float>::infinity();
        ++skyCount;
        continue;
      }
      // rayCamera has camera-space z = -1: its parameter at the ground is the z-depth.
      const Eigen::Vector3d ray = camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5);
      if (heightMeters > 0 && ray.y() < 0 && heightMeters / -ray.y() < backdropMeters) {
        depth = float(heightMeters / -ray.y());
        ++groundCount;
      }
    }
  }
  guess.skyFraction = double(skyCount) / double(guess.depthMeters.size());
  guess.groundFraction = double(groundCount) / double(guess.depthMeters.size());
  return guess;
}

}  // namespace pluvia
