#include "rain/drop_physics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace pluvia::rain {

double marshallPalmerSlopePerMm(double rainRateMmPerHour) {
  return 4.1 * std::pow(rainRateMmPerHour, -0.21);
}

double dropsPerCubicMeter(double rainRateMmPerHour, double minDiameterMm, double maxDiameterMm) {
  if (rainRateMmPerHour <= 0.0 || maxDiameterMm <= minDiameterMm) return 0.0;
  const double lambda = marshallPalmerSlopePerMm(rainRateMmPerHour);
  // Integral of N0 exp(-lambda D) from min to max.
  return kMarshallPalmerN0 / lambda *
         (std::exp(-lambda * minDiameterMm) - std::exp(-lambda * maxDiameterMm));
}

double sampleDiameterMm(double u, double rainRateMmPerHour, double minDiameterMm,
                        double maxDiameterMm) {
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

namespace {

// The Gamma functions work in x = Lambda D, where N(D) dD is proportional to x^2 exp(-x) dx
// (mu = 2): its regularised incomplete gammas P(3, x) and Q(3, x) = 1 - P have closed forms.
// Q = exp(-x) (1 + x + x^2 / 2) never cancels; P uses its series below 1, where 1 - Q would.
double gamma3Polynomial(double x) {
  return 1.0 + x + 0.5 * x * x;
}
double upperGamma3(double x) {
  return std::exp(-x) * gamma3Polynomial(x);
}
double logUpperGamma3(double x) {
  return -x + std::log(gamma3Polynomial(x));
}

double lowerGamma3(double x) {
  if (x >= 1.0) return 1.0 - upperGamma3(x);
  // exp(-x) sum_{k >= 3} x^k / k!: 20 terms are exact to rounding for x < 1.
  double term = x * x * x / 6.0, sum = 0.0;
  for (int k = 4; k < 24; ++k) {
    sum += term;
    term *= x / k;
  }
  return std::exp(-x) * sum;
}

// Beyond xLo + 64 the remaining mass is below 1e-25 of the total: capping there keeps an
// infinite upper end finite.
double capUpper(double xLo, double xHi) {
  return std::min(xHi, xLo + 64.0);
}

// Probability mass of x^2 exp(-x) / 2 on [xLo, xHi].
double gamma3Mass(double xLo, double xHi) {
  xHi = capUpper(xLo, xHi);
  return xLo >= 1.0 ? upperGamma3(xLo) - upperGamma3(xHi) : lowerGamma3(xHi) - lowerGamma3(xLo);
}

// The x in [xLo, xHi] with mass(xLo, x) = u mass(xLo, xHi), by Newton's method on log P below
// the median (2.67) and on log Q above it. Both are concave (the density is log-concave), so
// the iterates approach the root monotonically after at most one step (about 5 steps in all)
// and need no bracketing. The upper target is kept in logs scaled by exp(xLo), so far tails at
// tiny rain rates neither cancel nor underflow.
double sampleGamma3(double u, double xLo, double xHi) {
  xHi = capUpper(xLo, xHi);
  if (u <= 0.0) return xLo;
  const double polyLo = gamma3Polynomial(xLo);
  const double tailHi = std::exp(xLo - xHi) * gamma3Polynomial(xHi);
  const double logTargetQ = -xLo + std::log(polyLo - u * (polyLo - tailHi));
  double x;
  if (logTargetQ < std::log(0.5)) {
    x = std::max(xLo, 2.67);
    for (int iteration = 0; iteration < 60; ++iteration) {
      const double slope = -0.5 * x * x / gamma3Polynomial(x);  // d log Q / dx
      const double next = std::clamp(x - (logUpperGamma3(x) - logTargetQ) / slope, xLo, xHi);
      const bool done = std::abs(next - x) <= 1e-13 * x;
      x = next;
      if (done) break;
    }
  } else {
    const double pLo = lowerGamma3(xLo);
    const double logTargetP = std::log(pLo + u * (lowerGamma3(xHi) - pLo));
    // P(x) <= x^3 / 6, so this start lies left of the root.
    x = std::max(xLo, std::cbrt(6.0 * std::exp(logTargetP)));
    for (int iteration = 0; iteration < 60; ++iteration) {
      const double p = lowerGamma3(x);
      const double slope = 0.5 * x * x * std::exp(-x) / p;  // d log P / dx
      const double next = std::clamp(x - (std::log(p) - logTargetP) / slope, xLo, xHi);
      const bool done = std::abs(next - x) <= 1e-13 * std::max(x, 1e-300);
      x = next;
      if (done) break;
    }
  }
  return x;
}

}  // namespace

GammaParameters gammaParameters(double rainRateMmPerHour) {
  constexpr double mu = 2.0;
  const double mpSlope = marshallPalmerSlopePerMm(rainRateMmPerHour);
  // Same D0 = 3.67 / Lambda_MP, and the same third moment: N0 Gamma(mu + 4) / Lambda^(mu + 4)
  // = N0_MP Gamma(4) / Lambda_MP^4, with Gamma(6) = 120 and Gamma(4) = 6.
  const double slope = mpSlope * (3.67 + mu) / 3.67;
  const double n0 =
      kMarshallPalmerN0 * 6.0 * std::pow(slope, 6.0) / (std::pow(mpSlope, 4.0) * 120.0);
  return {n0, mu, slope};
}

double dropsPerCubicMeter(SizeDistribution distribution, double rainRateMmPerHour,
                          double minDiameterMm, double maxDiameterMm) {
  if (distribution == SizeDistribution::MarshallPalmer)
    return dropsPerCubicMeter(rainRateMmPerHour, minDiameterMm, maxDiameterMm);
  if (rainRateMmPerHour <= 0.0 || maxDiameterMm <= minDiameterMm) return 0.0;
  const GammaParameters g = gammaParameters(rainRateMmPerHour);
  const double lambda = g.slopePerMm;
  // Integral of N0 D^2 exp(-Lambda D) = N0 / Lambda^3 * Gamma(3) * mass.
  return g.n0 / (lambda * lambda * lambda) * 2.0 *
         gamma3Mass(lambda * std::max(0.0, minDiameterMm), lambda * maxDiameterMm);
}

double sampleDiameterMm(SizeDistribution distribution, double u, double rainRateMmPerHour,
                        double minDiameterMm, double maxDiameterMm) {
  if (distribution == SizeDistribution::MarshallPalmer)
    return sampleDiameterMm(u, rainRateMmPerHour, minDiameterMm, maxDiameterMm);
  // A rate of 0 draws no drops; any size it is asked for is that of a vanishing rain.
  const double lambda = gammaParameters(std::max(rainRateMmPerHour, 1e-6)).slopePerMm;
  const double lo = std::max(0.0, minDiameterMm);
  const double hi = std::max(lo, maxDiameterMm);
  const double d = sampleGamma3(std::clamp(u, 0.0, 1.0), lambda * lo, lambda * hi) / lambda;
  return std::clamp(d, lo, hi);
}

double gunnKinzerVelocityMetersPerSecond(double diameterMm) {
  // Gunn and Kinzer (1949), distilled water drops in still air at 1013 mb and 20 C.
  static constexpr std::array<double, 34> kDiameterMm = {
      0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.2, 1.4, 1.6, 1.8, 2.0, 2.2, 2.4,
      2.6, 2.8, 3.0, 3.2, 3.4, 3.6, 3.8, 4.0, 4.2, 4.4, 4.6, 4.8, 5.0, 5.2, 5.4, 5.6, 5.8};
  static constexpr std::array<double, 34> kVelocity = {
      0.27, 0.72, 1.17, 1.62, 2.06, 2.47, 2.87, 3.27, 3.67, 4.03, 4.64, 5.17,
      5.65, 6.09, 6.49, 6.90, 7.27, 7.57, 7.82, 8.06, 8.26, 8.44, 8.60, 8.72,
      8.83, 8.92, 8.98, 9.03, 9.07, 9.09, 9.12, 9.14, 9.16, 9.17};
  if (!(diameterMm > 0.0)) return 0.0;
  if (diameterMm < kDiameterMm.front()) {
    const double r = diameterMm / kDiameterMm.front();
    return kVelocity.front() * r * r;
  }
  if (diameterMm >= kDiameterMm.back()) return kVelocity.back();
  const size_t i = size_t(std::upper_bound(kDiameterMm.begin(), kDiameterMm.end(), diameterMm) -
                          kDiameterMm.begin());
  const double t = (diameterMm - kDiameterMm[i - 1]) / (kDiameterMm[i] - kDiameterMm[i - 1]);
  return kVelocity[i - 1] + t * (kVelocity[i] - kVelocity[i - 1]);
}

double terminalVelocity(VelocityModel model, double diameterMm) {
  return model == VelocityModel::GunnKinzer ? gunnKinzerVelocityMetersPerSecond(diameterMm)
                                            : terminalVelocityMetersPerSecond(diameterMm);
}

double rainExtinctionPerMeter(double rainRateMmPerHour) {
  if (!(rainRateMmPerHour > 0.0)) return 0.0;
  const double slope = marshallPalmerSlopePerMm(rainRateMmPerHour);
  return M_PI * kMarshallPalmerN0 / (slope * slope * slope) * 1e-6;  // mm^2 / m^3 -> 1/m
}

double rainVisibilityMeters(double rainRateMmPerHour) {
  const double sigma = rainExtinctionPerMeter(rainRateMmPerHour);
  return sigma > 0.0 ? 3.912 / sigma : std::numeric_limits<double>::infinity();
}

double oscillationFrequencyHz(double diameterMm) {
  constexpr double kSurfaceTensionNewtonsPerMeter = 0.0728, kWaterDensityKgPerCubicMeter = 1000.0;
  const double radiusMeters = 0.5e-3 * diameterMm;
  if (!(radiusMeters > 0.0)) return 0.0;
  const double omega =
      std::sqrt(8.0 * kSurfaceTensionNewtonsPerMeter /
                (kWaterDensityKgPerCubicMeter * radiusMeters * radiusMeters * radiusMeters));
  return omega / (2.0 * M_PI);
}

}  // namespace pluvia::rain
