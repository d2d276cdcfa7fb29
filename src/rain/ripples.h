#pragma once
// Ring ripples where drops strike standing water. A drop's impact leaves a crater whose collapse
// sends a packet of capillary-gravity waves outwards. Their dispersion on deep water (Lamb,
// Hydrodynamics, 6th ed. 1932, sec. 267) is
//   omega^2 = g k + (sigma / rho) k^3,   phase speed c(k) = sqrt(g / k + sigma k / rho),
// with a minimum c_min = (4 g sigma / rho)^(1/4) = 0.231 m/s at k_min = sqrt(rho g / sigma) =
// 366 rad/m (wavelength 1.71 cm), where the group speed equals the phase speed: the packet near
// k_min keeps its shape as it spreads, so that is the ring a camera sees; shorter waves run ahead
// and die within millimetres (viscosity), longer ones are barely raised by a millimetre drop.
// The ring's radius is R(t) = R0 + c_min t, R0 the crown's final radius (rain/splashes.h, 2 D).
//
// Its amplitude falls as the energy spreads over a growing ring whose packet disperses (A ~ 1/R)
// and as the wave is damped. Natural standing water carries a surface film, and a film-covered
// ("inextensible") surface damps capillary waves at gamma = k sqrt(nu omega / 8) (Lamb sec. 351,
// Miles 1967, J. Fluid Mech. 27), 1.19 / s at k_min, far above the clean surface's 2 nu k^2 =
// 0.27 / s; puddles' rings fade within a second, as the film's rate says. Height along the
// radius r at age t:
//   h(r, t) = A(t) exp(-(r - R)^2 / (2 w^2)) cos(k_min (r - R)),   w = lambda / 2,
//   A(t) = kInitialAmplitudePerDiameter D (R0 / R) exp(-gamma t).
// The initial amplitude, a tenth of the drop's diameter, is a look (the crater is about D deep),
// not a fit to footage. A ring lives until its steepest slope, about A k, falls under
// kMinVisibleSlope (a reflection tilted by 2 x 0.001 rad moves a pixel at a focal length of 500
// px).
#include "rain/splashes.h"

namespace pluvia::rain {

inline constexpr double kWaterSurfaceTension = 0.0728;      // N/m, 20 C
inline constexpr double kWaterDensity = 998.0;              // kg/m^3
inline constexpr double kWaterKinematicViscosity = 1.0e-6;  // m^2/s
inline constexpr double kInitialAmplitudePerDiameter = 0.1;
inline constexpr double kMinVisibleSlope = 1e-3;

// c(k), m/s, at wavenumber k (rad/m) on deep water.
double capillaryGravityPhaseSpeed(double wavenumberPerMeter);
// d omega / d k, m/s.
double capillaryGravityGroupSpeed(double wavenumberPerMeter);
// k_min, where the phase speed is least (and equals the group speed).
double minPhaseSpeedWavenumber();
// The film-covered surface's amplitude damping rate, 1/s, at k.
double filmDampingPerSecond(double wavenumberPerMeter);

// The ring of `impact` at `ageSeconds` after it (0 before the impact).
struct RippleRing {
  double radiusMeters = 0.0;
  double amplitudeMeters = 0.0;
  double packetWidthMeters = 0.0;  // w above
  double wavenumberPerMeter = 0.0;
};
RippleRing rippleRing(const Impact& impact, double ageSeconds);

// dh/dr at distance `radiusMeters` from the impact's point, for the ring above; 0 beyond 4 w
// from its crest.
double rippleRadialSlope(const RippleRing& ring, double radiusMeters);

// The age at which the ring's slope amplitude A k falls under kMinVisibleSlope.
double rippleLifeSeconds(const Impact& impact);

}  // namespace pluvia::rain
