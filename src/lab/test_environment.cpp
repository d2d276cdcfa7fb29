#include "lab/test_environment.h"

#include <cmath>

namespace pluvia::lab {

EquirectMap builtinTestEnvironment(int width) {
  const int height = width / 2;
  EquirectMap map(width, height);
  const double sunElevation = 30.0 * M_PI / 180.0, sunAzimuth = 0.6;
  const std::array<double, 3> sun = {std::cos(sunElevation) * std::sin(sunAzimuth),
                                     std::sin(sunElevation),
                                     -std::cos(sunElevation) * std::cos(sunAzimuth)};
  const double sunCos = std::cos(1.5 * M_PI / 180.0);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::array<double, 3> d = equirectTexelDirection(width, height, x, y);
      std::array<double, 3> radiance;
      if (d[1] >= 0.0) {
        const double t = d[1];  // 0 at the horizon, 1 at the zenith
        radiance = {0.9 - 0.5 * t, 1.0 - 0.35 * t, 1.2 - 0.1 * t};
      } else {
        radiance = {0.25, 0.2, 0.15};
      }
      const double azimuth = std::atan2(d[0], -d[2]);
      if (d[1] > -0.2 && d[1] < 0.35 && azimuth > 1.8 && azimuth < 2.6) radiance = {1.6, 0.15, 0.1};
      if (d[1] > -0.2 && d[1] < 0.25 && azimuth > -2.4 && azimuth < -1.7)
        radiance = {0.1, 0.9, 0.2};
      if (d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2] > sunCos)
        radiance = {2000.0, 1800.0, 1500.0};
      for (int c = 0; c < 3; ++c) map.texel(x, y)[c] = float(radiance[size_t(c)]);
    }
  }
  return map;
}

}  // namespace pluvia::lab
