#pragma once
// The transfer function D(theta) of a spherical raindrop, in closed form (Wang et al. 2006,
// section 4.2 and Appendices A-C).
//
// A ray travelling along the view direction hits the drop's disc at impact parameter
// b = sin(gamma) (gamma: angle of incidence). Term n = 1 is the external reflection, term n >= 2
// leaves after n - 2 internal reflections; it carries the power fraction
//   w_1 = R(gamma),   w_n = T(gamma)^2 R(gamma)^(n-2)
// and leaves at angle theta_n = Theta(zeta_n) from the view direction, where
//   zeta_n = pi - 2 gamma - (n - 1)(pi - 2 beta),   sin(beta) = sin(gamma) / eta.
// Rays are uniform over the disc, i.e. uniform in b^2, so D(theta), the outgoing power per unit
// solid angle, integrates to sum_n integral w_n d(b^2), which tends to 1 as the number of terms
// grows (R + T^2 sum R^(n-2) = 1 for every ray). By reciprocity the drop's radiance seen along v
// is the integral of D(angle(v, w)) L(w) dw.
//
// Two ways of using D, both stable everywhere (theta = 0 and pi, grazing gamma, the rainbow
// caustics where d theta_n / d gamma = 0, many terms, eta from 1.0001 to 2.5):
//  - integrals of D against smooth functions of cos(theta) (energy, SH coefficients) are taken
//    over gamma, where every integrand is smooth: cos(theta_n) = cos(zeta_n);
//  - D itself as a table of bins in cos(theta): the power falling in each bin divided by its
//    solid angle, so the integrable singularities at caustics and on the axis become finite
//    bin averages instead of samples of an infinite density.
#include <cstddef>
#include <vector>

namespace pluvia::optics {

struct DropOptics {
  double eta = 1.333;  // refractive index of water relative to air
  int terms = 9;       // N: terms n = 1..N kept (the paper keeps 9)
};

// w_n(gamma) above: the fraction of the power of a ray at incidence gamma leaving in term n.
double termPower(int n, double gamma, double eta);
// cos(theta_n(gamma)) = cos(zeta_n(gamma)).
double termCosTheta(int n, double gamma, double eta);
// The paper's xi_n(gamma): the intensity of term n per unit incident intensity, Appendix B,
// with xi_1 = R / 4. Infinite at caustics and where sin(theta_n) = 0 with d theta/d gamma != 0.
double termIntensity(int n, double gamma, double eta);

// D(theta) by Eq. (10): (1/pi) sum over n and every gamma with theta_n(gamma) = theta of
// xi_n(gamma), the branches found by bracketing and bisection. Where the density is singular
// (sin theta ~ 0, or a root at a caustic) it returns the average over the ring of half-width
// 1e-4 rad around theta instead, so the result is always finite.
double transferDensity(double theta, const DropOptics& optics);

// Total power of the first N terms: sum_n integral w_n d(b^2) (1 as N -> infinity).
double transferEnergy(const DropOptics& optics);
// Power of term n alone.
double termEnergy(int n, double eta);

// Zonal SH coefficients d_l = 2 pi integral D(theta) Y_l0(theta) sin(theta) d theta, l = 0..order.
std::vector<double> transferZonal(const DropOptics& optics, int order);

// D averaged over bins of equal width in mu = cos(theta): bin k covers
// mu in [-1 + k * 2/bins, -1 + (k + 1) * 2/bins]. Sum of density * 2 pi * (2 / bins) = energy.
struct TransferTable {
  std::vector<double> density;  // per steradian
  double binWidthMu() const { return 2.0 / double(density.size()); }
  // Linear interpolation between bin centres (clamped at the ends). Inline: the drop radiance
  // map looks it up a hundred million times per environment.
  double at(double mu) const {
    const int bins = int(density.size());
    const double position = (mu + 1.0) / binWidthMu() - 0.5;  // bin centres on integers
    if (position <= 0.0) return density.front();
    if (position >= bins - 1) return density.back();
    const int k = int(position);
    const double f = position - k;
    return density[std::size_t(k)] + f * (density[std::size_t(k) + 1] - density[std::size_t(k)]);
  }
};
TransferTable binTransfer(const DropOptics& optics, int bins);

// Power with cos(theta) >= mu: the exact cumulative of D, for ring averages and tests.
double powerAboveCosTheta(double mu, const DropOptics& optics);

}  // namespace pluvia::optics
