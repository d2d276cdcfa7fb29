#include "optics/drop_local_light.h"

#include <algorithm>
#include <cmath>

namespace pluvia::optics {

DropLocalLight dropLocalRadiance(const TransferTable& transfer,
                                 const std::vector<LocalLight>& lights, double betaPerMeter,
                                 const Vec3& drop, const Vec3& view) {
  std::array<double, 3> sum{0, 0, 0};
  DropLocalLight result;
  double brightest = 0.0;
  for (const LocalLight& light : lights) {
    const std::array<double, 3> w{light.positionMeters[0] - drop[0],
                                  light.positionMeters[1] - drop[1],
                                  light.positionMeters[2] - drop[2]};
    const double distance = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    // Inside the bulb the irradiance stays that of its surface.
    const double d = std::max(distance, light.radiusMeters);
    double cosView = 1.0, cosSpot = 1.0;
    if (distance > 0.0) {
      cosView = (view[0] * w[0] + view[1] * w[1] + view[2] * w[2]) / distance;
      // The spot's theta: between its axis and the light -> drop direction, -w.
      cosSpot = -(light.axis[0] * w[0] + light.axis[1] * w[1] + light.axis[2] * w[2]) / distance;
    }
    const double cone = spotFactor(light, cosSpot);
    if (cone <= 0.0) continue;
    const double irradiancePerIntensity = cone * std::exp(-betaPerMeter * d) / (d * d);
    const double D = transfer.at(std::clamp(cosView, -1.0, 1.0));
    double luminance = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double added = D * irradiancePerIntensity * light.rgbIntensity[size_t(c)];
      sum[size_t(c)] += added;
      luminance += added;
    }
    if (luminance > brightest && distance > 0.0) {
      brightest = luminance;
      result.towardsBrightest = {w[0] / distance, w[1] / distance, w[2] / distance};
    }
  }
  // Float's range bounds it (an intensity of 1e9 at the bulb's surface).
  result.rgb = {float(std::min(sum[0], 1e30)), float(std::min(sum[1], 1e30)),
                float(std::min(sum[2], 1e30))};
  return result;
}

}  // namespace pluvia::optics
