#include "stages/sun.h"

#include <cmath>

#include "image/luminance.h"

namespace pluvia {

Eigen::Vector3d sunDirection(double elevationDeg, double azimuthDeg) {
  const double e = elevationDeg * M_PI / 180.0, a = azimuthDeg * M_PI / 180.0;
  return {std::sin(a) * std::cos(e), std::sin(e), -std::cos(a) * std::cos(e)};
}

std::optional<Sun> findSun(const EquirectMap& environment) {
  if (environment.empty()) return std::nullopt;
  const EquirectMap map = resampleEquirect(environment, 256, 128);
  double total = 0.0, peak = -1.0;
  int px = 0, py = 0;
  for (int y = 0; y < map.height; ++y) {
    const double omega = equirectTexelSolidAngle(map.width, map.height, y);
    for (int x = 0; x < map.width; ++x) {
      const double l = rec709Luminance(map.texel(x, y));
      total += l * omega;
      if (l > peak) peak = l, px = x, py = y;
    }
  }
  const double mean = total / (4.0 * M_PI);
  if (!(peak > kSunContrast * mean)) return std::nullopt;
  const auto d = equirectTexelDirection(map.width, map.height, px, py);
  Sun sun;
  sun.direction = Eigen::Vector3d(d[0], d[1], d[2]).normalized();
  const double cosRadius = std::cos(kSunRadiusDeg * M_PI / 180.0);
  for (int y = 0; y < map.height; ++y) {
    const double omega = equirectTexelSolidAngle(map.width, map.height, y);
    for (int x = 0; x < map.width; ++x) {
      const auto t = equirectTexelDirection(map.width, map.height, x, y);
      if (Eigen::Vector3d(t[0], t[1], t[2]).dot(sun.direction) < cosRadius) continue;
      const float* rgb = map.texel(x, y);
      for (int c = 0; c < 3; ++c)
        sun.irradianceRgb[size_t(c)] += std::max(0.0, rgb[c] - mean) * omega;
    }
  }
  return sun;
}

}  // namespace pluvia
