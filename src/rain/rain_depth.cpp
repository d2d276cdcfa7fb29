#include "rain/rain_depth.h"

#include "rain/drop_physics.h"

namespace pluvia::rain {

double medianVolumeDiameterMm(double rainRateMmPerHour) {
  return 3.67 / marshallPalmerSlopePerMm(rainRateMmPerHour);
}

double streakDepthMeters(double focalPx, double rainRateMmPerHour, double sizeScale) {
  const double medianDiameterMeters = 1e-3 * medianVolumeDiameterMm(rainRateMmPerHour) * sizeScale;
  return kVisibleDepthOverOnePixel * focalPx * medianDiameterMeters;
}

}  // namespace pluvia::rain
