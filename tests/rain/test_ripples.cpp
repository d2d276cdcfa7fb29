// Ripples: the capillary-gravity dispersion against its closed-form minimum, the ring's radius
// against age at that phase speed, the slope as the derivative of the height profile, and the
// ring's life ending where its slope is under visibility.
#include <cmath>

#include <gtest/gtest.h>

#include "rain/ripples.h"

using namespace pluvia::rain;

namespace {

Impact impactOf(double diameterMm) {
  Impact impact;
  impact.diameterMm = diameterMm;
  impact.speedMetersPerSecond = 6.0;
  return impact;
}

// The height profile of rain/ripples.h, written out independently of the slope code.
double height(const RippleRing& ring, double r) {
  const double u = r - ring.radiusMeters, w = ring.packetWidthMeters;
  return ring.amplitudeMeters * std::exp(-u * u / (2 * w * w)) *
         std::cos(ring.wavenumberPerMeter * u);
}

}  // namespace

TEST(Ripples, ThePhaseSpeedsMinimumIsLambsClosedForm) {
  // c_min = (4 g sigma / rho)^(1/4) at k_min = sqrt(rho g / sigma): 0.2313 m/s, 366 rad/m.
  const double kMin = minPhaseSpeedWavenumber();
  EXPECT_NEAR(kMin, std::sqrt(998.0 * 9.81 / 0.0728), 1e-9);
  EXPECT_NEAR(kMin, 366.7, 0.5);
  const double cMin = std::pow(4.0 * 9.81 * 0.0728 / 998.0, 0.25);
  EXPECT_NEAR(capillaryGravityPhaseSpeed(kMin), cMin, 1e-9);
  EXPECT_NEAR(cMin, 0.2313, 5e-4);
  // A minimum: both sides are faster, and there the group speed equals the phase speed.
  EXPECT_GT(capillaryGravityPhaseSpeed(0.8 * kMin), cMin);
  EXPECT_GT(capillaryGravityPhaseSpeed(1.25 * kMin), cMin);
  EXPECT_NEAR(capillaryGravityGroupSpeed(kMin), cMin, 1e-9);
  // Long gravity waves travel at half their phase speed, short capillary ones at 3/2 of it.
  EXPECT_NEAR(capillaryGravityGroupSpeed(1.0) / capillaryGravityPhaseSpeed(1.0), 0.5, 1e-3);
  EXPECT_NEAR(capillaryGravityGroupSpeed(1e5) / capillaryGravityPhaseSpeed(1e5), 1.5, 1e-3);
}

TEST(Ripples, TheRingSpreadsAtTheMinimumPhaseSpeedFromTheCrownsRadius) {
  const Impact impact = impactOf(2.0);
  const double c = capillaryGravityPhaseSpeed(minPhaseSpeedWavenumber());
  EXPECT_NEAR(rippleRing(impact, 0.0).radiusMeters, 0.004, 1e-12);  // the crown's 2 D
  for (double t : {0.05, 0.2, 0.5}) {
    const RippleRing ring = rippleRing(impact, t);
    EXPECT_NEAR(ring.radiusMeters, 0.004 + c * t, 1e-12) << t;
  }
  // Measured as footage would measure it: the outermost crest's radius at two ages.
  auto crest = [&](double t) {
    const RippleRing ring = rippleRing(impact, t);
    double best = 0.0, at = 0.0;
    for (double r = 0.0; r < 0.5; r += 1e-5)
      if (height(ring, r) > best) best = height(ring, r), at = r;
    return at;
  };
  EXPECT_NEAR((crest(0.4) - crest(0.1)) / 0.3, c, 0.01 * c);
}

TEST(Ripples, TheSlopeIsTheHeightsDerivativeAndVanishesAwayFromTheRing) {
  const RippleRing ring = rippleRing(impactOf(3.0), 0.3);
  const double h = 1e-7;
  for (double u = -3.0; u <= 3.0; u += 0.25) {
    const double r = ring.radiusMeters + u * ring.packetWidthMeters;
    const double numeric = (height(ring, r + h) - height(ring, r - h)) / (2 * h);
    EXPECT_NEAR(rippleRadialSlope(ring, r), numeric,
                1e-6 * ring.amplitudeMeters / ring.packetWidthMeters + 1e-9)
        << u;
  }
  EXPECT_EQ(rippleRadialSlope(ring, ring.radiusMeters + 5 * ring.packetWidthMeters), 0.0);
  EXPECT_EQ(rippleRadialSlope(ring, 0.0), 0.0);
}

TEST(Ripples, ALifeEndsWhereTheSlopeFallsUnderVisibilityAndGrowsWithTheDrop) {
  double last = 0.0;
  for (double d : {1.0, 2.0, 4.0}) {
    const Impact impact = impactOf(d);
    const double life = rippleLifeSeconds(impact);
    EXPECT_GT(life, last) << d;
    last = life;
    auto steep = [&](double t) {
      const RippleRing ring = rippleRing(impact, t);
      return ring.amplitudeMeters * ring.wavenumberPerMeter;
    };
    EXPECT_GT(steep(0.99 * life), kMinVisibleSlope) << d;
    EXPECT_LE(steep(1.01 * life), kMinVisibleSlope) << d;
  }
  // A 2 mm drop's ring fades within a second, some 14 cm across: a puddle's ring.
  const double life = rippleLifeSeconds(impactOf(2.0));
  EXPECT_GT(life, 0.3);
  EXPECT_LT(life, 1.0);
  // The film damps at k sqrt(nu omega / 8), over four times the clean surface's 2 nu k^2.
  const double k = minPhaseSpeedWavenumber();
  EXPECT_GT(filmDampingPerSecond(k), 4.0 * 2.0 * kWaterKinematicViscosity * k * k);
  // A drop too small to raise a visible ring has none; none before its impact.
  EXPECT_EQ(rippleLifeSeconds(impactOf(0.02)), 0.0);  // A k = 0.1 D k = 7e-4
  EXPECT_EQ(rippleRing(impactOf(2.0), -0.1).amplitudeMeters, 0.0);
}
