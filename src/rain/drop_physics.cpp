#include "rain/drop_physics.h"

#include <algorithm>
#include <cmath>

namespace pluvia::rain {

double marshallPalmerSlopePerMm(double rainRateMmPerHour) { return 4.1 * std::pow(rainRateMmPerHour, -0.21); }

double dropsPerCubicMeter(double rainRateMmPerHour, double minDiameterMm, double maxDiameterMm) {
  if (rainRateMmPerHour <= 0.0 || maxDiameterMm <= minDiameterMm) return 0.0;
  const double lambda = marshallPalmerSlopePerMm(rainRateMmPerHour);
  // Integral of N0 exp(-lambda D) from min to max.
  return kMarshallPalmerN0 / lambda * (std::exp(-lambda * minDiameterMm) - std::exp(-lambda * maxDiameterMm));
}

double sampleDiameterMm(double u, double rainRateMmPerHour, double minDiameterMm, double maxDiameterMm) {
  const double lambda = marshallPalmerSlopePerMm(std::max(rainRateMmPerHour, 1e-6));
  const double a = std::exp(-lambda * minDiameterMm);
  const double b = std::exp(-lambda * maxDiameterMm);
  // Solve (a - exp(-lambda D)) / (a - b) = u for D.
  const double d = -std::log(a - u * (a - b)) / lambda;
  return std::clamp(d, minDiameterMm, maxDiameterMm);
}

double terminalVelocityMetersPerSecond(double diameterMm) {
  return std::max(0.0, 9.65 - 10.3 * std::exp(-0.6 * diameterMm));
}

}  // namespace pluvia::rain
