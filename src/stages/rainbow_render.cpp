#include "stages/rainbow_render.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "util/parallel.h"

namespace pluvia {
namespace {

constexpr double kDeg = M_PI / 180.0;
// The bows and their smoothing lie within these angles from the antisolar point.
constexpr double kNearestBowDeg = 38.0, kFarthestBowDeg = 56.0;
// Nodes of theta at most this angle apart (addRainbow).
constexpr double kNodeRadians = 0.005;
constexpr int kMaxNodeStepPx = 16;

Eigen::Vector3d worldRay(const Camera& camera, double px, double py) {
  return (camera.worldFromCamera * camera.rayCamera(px, py)).normalized();
}

}  // namespace

void addRainbow(Image& image, const Camera& camera, const Sun& sun,
                const std::array<optics::RainbowProfile, 3>& profiles,
                const RainbowVolume& volume) {
  if (sun.direction.y() <= 0.0 || volume.rainExtinctionPerMeter <= 0.0) return;
  const std::vector<float>* depth = image.findPlane(kDepthPlane);
  const double sigmaT = volume.rainExtinctionPerMeter + volume.fogExtinctionPerMeter;
  const double albedo = 0.5 * volume.rainExtinctionPerMeter / sigmaT;
  const int width = image.width, height = image.height;
  // theta is smooth over the picture (but at the antisolar point, a cone's tip where the
  // profile is flat): looked up at nodes kNodeRadians apart (10 px at 1080p and 50 deg) and
  // interpolated bilinearly, it errs by about kNodeRadians^2 / 8 / tan(theta) (a few
  // ten-thousandths of a degree on the bows, whose profile is binned at 0.05 deg).
  const int step = std::clamp(int(kNodeRadians * camera.focalPx), 1, kMaxNodeStepPx);
  const int nx = (width - 1 + step - 1) / step + 1, ny = (height - 1 + step - 1) / step + 1;
  auto nodeCoordinate = [step](int k, int size) { return std::min(k * step, size - 1); };
  std::vector<double> thetas(static_cast<size_t>(nx) * static_cast<size_t>(ny));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double c =
          worldRay(camera, nodeCoordinate(i, width) + 0.5, nodeCoordinate(j, height) + 0.5)
              .dot(sun.direction);
      thetas[size_t(j) * size_t(nx) + size_t(i)] = std::acos(std::clamp(c, -1.0, 1.0)) / kDeg;
    }
  const double inverseFocal = 1.0 / camera.focalPx;
  // 1 - exp(-sigma_t s) of the shower's whole extent: every sky pixel's.
  const double throughShower = -std::expm1(-sigmaT * volume.showerExtentMeters);
  forEachRow(height, [&](int y) {
    const int j0 = y / step, j1 = std::min(j0 + 1, ny - 1);
    const int y0 = nodeCoordinate(j0, height), y1 = nodeCoordinate(j1, height);
    const double fy = y1 > y0 ? double(y - y0) / double(y1 - y0) : 0.0;
    const double dy = (y + 0.5 - camera.cy) * inverseFocal;
    const double* row0 = thetas.data() + size_t(j0) * size_t(nx);
    const double* row1 = thetas.data() + size_t(j1) * size_t(nx);
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      const double z = depth ? double((*depth)[i]) : std::numeric_limits<double>::infinity();
      double through = throughShower;
      if (std::isfinite(z)) {
        // The path along the pixel's ray: z-depth times the ray's length at z = 1.
        const double dx = (x + 0.5 - camera.cx) * inverseFocal;
        const double path =
            std::min(z * std::sqrt(dx * dx + dy * dy + 1.0), volume.showerExtentMeters);
        if (!(path > 0.0)) continue;
        through = 1.0 - double(std::exp(-float(sigmaT * path)));
      }
      const int i0 = x / step, i1 = std::min(i0 + 1, nx - 1);
      const int x0 = nodeCoordinate(i0, width), x1 = nodeCoordinate(i1, width);
      const double fx = x1 > x0 ? double(x - x0) / double(x1 - x0) : 0.0;
      const double top = row0[i0] + fx * (row0[i1] - row0[i0]);
      const double bottom = row1[i0] + fx * (row1[i1] - row1[i0]);
      const double thetaDeg = top + fy * (bottom - top);
      const double scattered = volume.strength * albedo * through;
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
