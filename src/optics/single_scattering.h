#pragma once
// Single scattering of a local light in a homogeneous medium (rain and fog): the glow a camera
// sees around a lamp and the beam of a spotlight (Huang et al. 2006 section 2, after Sun et al.
// 2005, "A practical analytic single scattering model").
//
// Camera at the origin, a ray in unit direction r, a light at s with intensity I (what a
// lamp sends per steradian, in scene-linear units times m^2), extinction beta per metre (all of
// it scattering: water absorbs little), phase function k = 1 / (4 pi) as in Huang et al. The
// radiance the ray gathers up to distance X (the scene depth there) is
//   L = integral_0^X beta k I(theta(x)) exp(-beta (d(x) + x)) / d(x)^2 dx,   d(x) = |x r - s|.
// With T = beta |s|, cos(gamma) = r.s / |s|, h = T sin(gamma) and the substitution
// beta x = T cos(gamma) + h tan(xi), epsilon = pi/4 + xi/2 (Sun et al.), an isotropic light gives
//   L = beta^2 I exp(-T cos gamma) / (2 pi h) * [F(h, e(X)) - F(h, gamma/2)],
//   F(u, v) = integral_0^v exp(-u tan e) de,   e(x) = pi/4 + atan((beta x - T cos gamma) / h) / 2,
// Huang et al.'s Eq. (9)-(10) with the upper limit of a finite ray. A spotlight,
//   I(theta) = I0 ((1 - q)(cos theta - cos A) / (1 - cos A) + q) inside its cone, 0 outside,
// is integrated over the parts of the ray inside the cone. Its constant part is the isotropic
// integral; its cos(theta) = ((x r - s).a) / d part needs two more tables of one shape,
//   S(u, v) = integral_0^v sin(2e) exp(-u tan e) de,   C(u, v) = integral_0^v cos(2e) exp(-u tan e)
//   de,
// since (with t = beta x and the same substitution) dt / s^3 = 2 sin(2e) de / h^2 and
// t = T cos gamma - h cot(2e). These play the part of Huang et al.'s F0-F3 (Eq. 20), derived
// here with Sun et al.'s substitution so that all three tables share F's axes.
//
// Stable everywhere: a ray through the light (h -> 0) sees the lamp's own bulb, so the light is a
// ball of radius lightRadiusMeters and h never drops below beta times it; a path whose
// attenuation is below exp(-60) gives 0 rather than 0 * infinity; every result is finite and
// non-negative.
#include <array>
#include <vector>

#include "optics/local_light.h"

namespace pluvia::optics {

// The three integrals over [e0, e1] times exp(logScale), with the exponent of the lower end
// folded into logScale before anything is exponentiated: the prefactor exp(-T cos gamma) is
// huge exactly where exp(-h tan e) is tiny (a light behind the camera), and their product, the
// attenuation along the path, is what is kept. Tables hold the complementary integrals scaled
// by exp(u tan v) and (1 + u),
//   G_F(u, v) = (1 + u) integral_v^(pi/2) exp(-u (tan e - tan v)) de   (and G_S, G_C likewise),
// smooth and of order 1 on (a, v), a = u / (1 + u) in [0, 1] (u = infinity included), v in
// [0, pi/2]; looked up bilinearly. Then
//   integral_e0^e1 = exp(-u tan e0) G(u, e0) / (1 + u) - exp(-u tan e1) G(u, e1) / (1 + u).
enum class ScatteringIntegral { F, S, C };

class ScatteringTables {
 public:
  ScatteringTables(int aSamples = 128, int vSamples = 128);
  double integral(ScatteringIntegral which, double u, double e0, double e1,
                  double logScale = 0.0) const;
  // F from e0 to e1 given as slopes t (e = pi/4 + atan(t) / 2, the substitution's own variable):
  // the same as integral(F, ...) without a tangent, since tan(pi/4 + atan(t) / 2) = t +
  // sqrt(1 + t^2). The halo of a point light, per pixel.
  double integralFromSlopes(double u, double t0, double t1, double logScale) const;
  int aSamples() const { return aSamples_; }
  int vSamples() const { return vSamples_; }

 private:
  double lookup(const std::vector<double>& table, double u, double v) const;
  int aSamples_;
  int vSamples_;
  std::vector<double> f_, s_, c_;
};

// The same by adaptive quadrature of exp(logScale - u tan e) times 1, sin 2e or cos 2e: the
// tables' reference.
double scatteringIntegral(ScatteringIntegral which, double u, double e0, double e1,
                          double logScale = 0.0);

// L above per unit intensity (I0 = 1, rgbIntensity not used) along unit ray `ray`, up to
// `rayLengthMeters` (infinity for the sky), through a medium of extinction `betaPerMeter`.
double inscatteredRadiance(const ScatteringTables& tables, const LocalLight& light, const Vec3& ray,
                           double rayLengthMeters, double betaPerMeter);
// The same integral marched numerically along the ray (adaptive Simpson on each part inside the
// cone, split at the point nearest the light): the reference for the tables.
double inscatteredRadianceReference(const LocalLight& light, const Vec3& ray,
                                    double rayLengthMeters, double betaPerMeter);

// The parts [x0, x1] of the ray, x in [0, rayLengthMeters], lit by the light (all of it for an
// isotropic light), in increasing order.
std::vector<std::array<double, 2>> litIntervals(const LocalLight& light, const Vec3& ray,
                                                double rayLengthMeters, double betaPerMeter);

}  // namespace pluvia::optics
