#include "rain/ripples.h"

#include <cmath>

namespace pluvia::rain {
namespace {

// Packet half widths out to which the slope is drawn: exp(-8) of the crest beyond.
constexpr double kPacketReach = 4.0;

double crownFinalRadiusMeters(const Impact& impact) {
  return 2.0 * impact.diameterMm * 1e-3;  // rain/splashes.h: the crown opens to 2 D
}

}  // namespace

double capillaryGravityPhaseSpeed(double k) {
  return std::sqrt(kGravity / k + kWaterSurfaceTension * k / kWaterDensity);
}

double capillaryGravityGroupSpeed(double k) {
  const double omega = k * capillaryGravityPhaseSpeed(k);
  return (kGravity + 3.0 * kWaterSurfaceTension * k * k / kWaterDensity) / (2.0 * omega);
}

double minPhaseSpeedWavenumber() {
  return std::sqrt(kWaterDensity * kGravity / kWaterSurfaceTension);
}

double filmDampingPerSecond(double k) {
  const double omega = k * capillaryGravityPhaseSpeed(k);
  return k * std::sqrt(kWaterKinematicViscosity * omega / 8.0);
}

RippleRing rippleRing(const Impact& impact, double ageSeconds) {
  RippleRing ring;
  if (!(ageSeconds >= 0.0) || impact.diameterMm <= 0.0) return ring;
  const double k = minPhaseSpeedWavenumber();
  const double start = crownFinalRadiusMeters(impact);
  ring.wavenumberPerMeter = k;
  ring.radiusMeters = start + capillaryGravityPhaseSpeed(k) * ageSeconds;
  ring.packetWidthMeters = M_PI / k;  // half a wavelength
  ring.amplitudeMeters = kInitialAmplitudePerDiameter * impact.diameterMm * 1e-3 *
                         (start / ring.radiusMeters) *
                         std::exp(-filmDampingPerSecond(k) * ageSeconds);
  return ring;
}

double rippleRadialSlope(const RippleRing& ring, double r) {
  const double u = r - ring.radiusMeters, w = ring.packetWidthMeters;
  if (!(w > 0.0) || std::abs(u) > kPacketReach * w) return 0.0;
  const double k = ring.wavenumberPerMeter;
  const double envelope = std::exp(-u * u / (2.0 * w * w));
  // d/du [e(u) cos(k u)] = e(u) (-u / w^2 cos(k u) - k sin(k u))
  return ring.amplitudeMeters * envelope * (-u / (w * w) * std::cos(k * u) - k * std::sin(k * u));
}

double rippleLifeSeconds(const Impact& impact) {
  // A k falls monotonically with age: bisect where it crosses kMinVisibleSlope.
  auto steep = [&](double t) {
    const RippleRing ring = rippleRing(impact, t);
    return ring.amplitudeMeters * ring.wavenumberPerMeter;
  };
  if (steep(0.0) <= kMinVisibleSlope) return 0.0;
  double lo = 0.0, hi = 0.25;
  while (steep(hi) > kMinVisibleSlope && hi < 60.0) hi *= 2.0;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (steep(mid) > kMinVisibleSlope ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace pluvia::rain
