#include "stages/rainbow_render.h"

#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

namespace pluvia {
namespace {

constexpr double kDeg = M_PI / 180.0;
// The bows and their smoothing lie within these angles from the antisolar point.
constexpr double kNearestBowDeg = 38.0, kFarthestBowDeg = 56.0;

Eigen::Vector3d worldRay(const Camera& camera, double px, double py) {
  return (camera.worldFromCamera * camera.rayCamera(px, py)).normalized();
}

}  // namespace

void addRainbow(Image& image, const Camera& camera, const Sun& sun,
                const std::array<optics::RainbowProfile, 3>& profiles,
                const RainbowVolume& volume) {
  if (sun.direction.y() <= 0.0 || volume.rainExtinctionPerMeter <= 0.0) return;
  const std::vector<float>* depth = image.findPlane("depth");
  const double sigmaT = volume.rainExtinctionPerMeter + volume.fogExtinctionPerMeter;
  const double albedo = 0.5 * volume.rainExtinctionPerMeter / sigmaT;
  const int width = image.width;
  tbb::parallel_for(0, image.height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      const Eigen::Vector3d rayCam = camera.rayCamera(x + 0.5, y + 0.5);  // z = -1
      const Eigen::Vector3d view = (camera.worldFromCamera * rayCam).normalized();
      const double thetaDeg = std::acos(std::clamp(view.dot(sun.direction), -1.0, 1.0)) / kDeg;
      const double z = depth ? double((*depth)[i]) : std::numeric_limits<double>::infinity();
      const double path = std::isfinite(z) ? std::min(z * rayCam.norm(), volume.showerExtentMeters)
                                           : volume.showerExtentMeters;
      if (!(path > 0.0)) continue;
      const double scattered = volume.strength * albedo * (1.0 - std::exp(-sigmaT * path));
      float* rgba = image.rgba.data() + i * 4;
      for (int c = 0; c < 3; ++c)
        rgba[c] +=
            float(sun.irradianceRgb[size_t(c)] * profiles[size_t(c)].at(thetaDeg) * scattered);
    }
  });
}

std::string rainbowHiddenReason(const Camera& camera, const Eigen::Vector3d& sunDirection) {
  const double elevationDeg = std::asin(std::clamp(sunDirection.y(), -1.0, 1.0)) / kDeg;
  if (elevationDeg <= 0.0)
    return fmt::format("the sun is {:.1f} deg below the horizon", -elevationDeg);
  const Eigen::Vector3d antisolar = -sunDirection.normalized();
  double nearest = 180.0, farthest = 0.0;
  constexpr int kSteps = 48;
  for (int j = 0; j <= kSteps; ++j)
    for (int i = 0; i <= kSteps; ++i) {
      const Eigen::Vector3d v =
          worldRay(camera, camera.width * double(i) / kSteps, camera.height * double(j) / kSteps);
      const double a = std::acos(std::clamp(v.dot(antisolar), -1.0, 1.0)) / kDeg;
      nearest = std::min(nearest, a), farthest = std::max(farthest, a);
    }
  if (farthest < kNearestBowDeg || nearest > kFarthestBowDeg)
    return fmt::format(
        "the view spans {:.0f}..{:.0f} deg from the antisolar point, the bows lie at "
        "{:.0f}..{:.0f}",
        nearest, farthest, kNearestBowDeg, kFarthestBowDeg);
  return "";
}

}  // namespace pluvia
