#include "optics/drop_transfer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "optics/fresnel.h"
#include "optics/legendre.h"

namespace pluvia::optics {
namespace {

constexpr double kHalfPi = M_PI / 2.0;
// Cells of the gamma grid on which every integral is taken (4-point Gauss-Legendre per cell)
// and on which the branches theta_n(gamma) = theta are bracketed. theta_n turns at most n times
// over [0, pi/2], so 4096 cells resolve every branch up to the 50 terms we support.
constexpr int kGammaCells = 4096;
constexpr std::array<double, 4> kGaussNodes = {-0.8611363115940526, -0.3399810435848563,
                                               0.3399810435848563, 0.8611363115940526};
constexpr std::array<double, 4> kGaussWeights = {0.3478548451374538, 0.6521451548625461,
                                                 0.6521451548625461, 0.3478548451374538};
// Ring half-width used where D is singular.
constexpr double kRingHalfWidthRad = 1e-4;

void checkOptics(const DropOptics& optics) {
  if (!(optics.eta > 1.0 && optics.eta <= 3.0)) {
    throw std::invalid_argument("refractive index must be in (1, 3], got " +
                                std::to_string(optics.eta));
  }
  if (optics.terms < 1 || optics.terms > 200) {
    throw std::invalid_argument("terms must be in 1..200, got " + std::to_string(optics.terms));
  }
}

double gammaCellWidth() {
  return kHalfPi / kGammaCells;
}

// Integral over gamma in [a, b] of f(gamma) * d(b^2)/d(gamma) = f * sin(2 gamma), 4-point Gauss.
template <typename F>
double integrateOverDisc(double a, double b, F&& f) {
  const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
  double sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    const double gamma = mid + half * kGaussNodes[i];
    sum += kGaussWeights[i] * f(gamma) * std::sin(2.0 * gamma);
  }
  return sum * half;
}

// The gamma in [a, b] where g changes sign (g(a), g(b) of opposite signs), by bisection.
template <typename G>
double bisect(double a, double b, G&& g) {
  double ga = g(a);
  for (int i = 0; i < 80 && b - a > 1e-15; ++i) {
    const double m = 0.5 * (a + b);
    const double gm = g(m);
    if ((gm >= 0.0) == (ga >= 0.0)) {
      a = m;
      ga = gm;
    } else {
      b = m;
    }
  }
  return 0.5 * (a + b);
}

double refractionAngle(double gamma, double eta) {
  return std::asin(std::sin(gamma) / eta);
}

}  // namespace

double termPower(int n, double gamma, double eta) {
  const double r = fresnelReflectance(std::cos(gamma), eta);
  if (n == 1) return r;
  const double t = 1.0 - r;
  return t * t * std::pow(r, n - 2);
}

double termCosTheta(int n, double gamma, double eta) {
  const double beta = refractionAngle(gamma, eta);
  const double zeta = M_PI - 2.0 * gamma - (n - 1) * (M_PI - 2.0 * beta);
  return std::cos(zeta);
}

double termIntensity(int n, double gamma, double eta) {
  const double r = fresnelReflectance(std::cos(gamma), eta);
  if (n == 1) return r / 4.0;
  const double beta = refractionAngle(gamma, eta);
  const double t = 1.0 - r;
  const double denominator =
      4.0 * std::abs(std::sin(2.0 * (n - 1) * beta - 2.0 * gamma) *
                     ((n - 1) * std::cos(gamma) / (eta * std::cos(beta)) - 1.0));
  return t * t * std::pow(r, n - 2) * std::sin(2.0 * gamma) / denominator;
}

double termEnergy(int n, double eta) {
  const double h = gammaCellWidth();
  double sum = 0.0;
  for (int cell = 0; cell < kGammaCells; ++cell) {
    sum += integrateOverDisc(cell * h, (cell + 1) * h,
                             [&](double gamma) { return termPower(n, gamma, eta); });
  }
  return sum;
}

double transferEnergy(const DropOptics& optics) {
  checkOptics(optics);
  double sum = 0.0;
  for (int n = 1; n <= optics.terms; ++n) sum += termEnergy(n, optics.eta);
  return sum;
}

std::vector<double> transferZonal(const DropOptics& optics, int order) {
  checkOptics(optics);
  if (order < 0 || order > 64) throw std::invalid_argument("SH order must be in 0..64");
  std::vector<double> zonal(size_t(order) + 1, 0.0);
  std::vector<double> legendre(size_t(order) + 1);
  const double h = gammaCellWidth();
  for (int cell = 0; cell < kGammaCells; ++cell) {
    const double half = 0.5 * h, mid = (cell + 0.5) * h;
    for (int i = 0; i < 4; ++i) {
      const double gamma = mid + half * kGaussNodes[i];
      const double weight = kGaussWeights[i] * half * std::sin(2.0 * gamma);
      for (int n = 1; n <= optics.terms; ++n) {
        const double power = termPower(n, gamma, optics.eta) * weight;
        legendrePolynomials(termCosTheta(n, gamma, optics.eta), legendre);
        for (int l = 0; l <= order; ++l) zonal[size_t(l)] += power * legendre[size_t(l)];
      }
    }
  }
  // Y_l0 = sqrt((2l + 1) / (4 pi)) P_l(cos theta).
  for (int l = 0; l <= order; ++l) zonal[size_t(l)] *= std::sqrt((2.0 * l + 1.0) / (4.0 * M_PI));
  return zonal;
}

double powerAboveCosTheta(double mu, const DropOptics& optics) {
  checkOptics(optics);
  const double h = gammaCellWidth();
  double sum = 0.0;
  for (int n = 1; n <= optics.terms; ++n) {
    auto excess = [&](double gamma) { return termCosTheta(n, gamma, optics.eta) - mu; };
    auto power = [&](double gamma) { return termPower(n, gamma, optics.eta); };
    double previous = excess(0.0);
    for (int cell = 0; cell < kGammaCells; ++cell) {
      const double a = cell * h, b = (cell + 1) * h;
      const double next = excess(b);
      if (previous >= 0.0 && next >= 0.0) {
        sum += integrateOverDisc(a, b, power);
      } else if (previous >= 0.0 || next >= 0.0) {
        const double root = bisect(a, b, excess);
        sum +=
            previous >= 0.0 ? integrateOverDisc(a, root, power) : integrateOverDisc(root, b, power);
      }
      previous = next;
    }
  }
  return sum;
}

double transferDensity(double theta, const DropOptics& optics) {
  checkOptics(optics);
  theta = std::clamp(theta, 0.0, M_PI);
  auto ringAverage = [&] {
    const double lo = std::max(0.0, theta - kRingHalfWidthRad);
    const double hi = std::min(M_PI, theta + kRingHalfWidthRad);
    const double muHi = std::cos(lo), muLo = std::cos(hi);
    const double power = powerAboveCosTheta(muLo, optics) - powerAboveCosTheta(muHi, optics);
    return power / (2.0 * M_PI * (muHi - muLo));
  };
  // On the axis every branch that reaches it is singular (sin theta = 0 in the denominator).
  if (std::sin(theta) < 1e-3) return ringAverage();

  const double mu = std::cos(theta);
  const double h = gammaCellWidth();
  double sum = 0.0;
  for (int n = 1; n <= optics.terms; ++n) {
    auto excess = [&](double gamma) { return termCosTheta(n, gamma, optics.eta) - mu; };
    double previous = excess(0.0);
    for (int cell = 0; cell < kGammaCells; ++cell) {
      const double next = excess((cell + 1) * h);
      if ((previous >= 0.0) != (next >= 0.0)) {
        const double root = bisect(cell * h, (cell + 1) * h, excess);
        const double xi = termIntensity(n, root, optics.eta);
        // A root at a caustic (d theta / d gamma = 0): the density there is infinite.
        if (!std::isfinite(xi) || xi > 1e6) return ringAverage();
        sum += xi;
      }
      previous = next;
    }
  }
  return sum / M_PI;
}

TransferTable binTransfer(const DropOptics& optics, int bins) {
  checkOptics(optics);
  if (bins < 2) throw std::invalid_argument("transfer table needs at least 2 bins");
  // Each segment of a fine gamma grid carries its exact power (w at the midpoint times the
  // d(b^2) of the segment); it is spread evenly over the range of cos(theta) the segment
  // sweeps, so a caustic (where the segment sweeps almost nothing) still lands in one bin.
  constexpr int kSegments = 1 << 15;
  std::vector<double> power(size_t(bins), 0.0);
  const double binWidth = 2.0 / bins;
  auto binOf = [&](double mu) { return std::clamp(int((mu + 1.0) / binWidth), 0, bins - 1); };
  const double h = kHalfPi / kSegments;
  for (int n = 1; n <= optics.terms; ++n) {
    double muStart = termCosTheta(n, 0.0, optics.eta);
    for (int s = 0; s < kSegments; ++s) {
      const double g0 = s * h, g1 = (s + 1) * h, gm = 0.5 * (g0 + g1);
      const double muMid = termCosTheta(n, gm, optics.eta);
      const double muEnd = termCosTheta(n, g1, optics.eta);
      const double segmentPower = termPower(n, gm, optics.eta) *
                                  (std::sin(g1) * std::sin(g1) - std::sin(g0) * std::sin(g0));
      const double lo = std::min({muStart, muMid, muEnd}), hi = std::max({muStart, muMid, muEnd});
      const int first = binOf(lo), last = binOf(hi);
      if (first == last) {
        power[size_t(first)] += segmentPower;
      } else {
        for (int k = first; k <= last; ++k) {
          const double overlap =
              std::min(hi, -1.0 + (k + 1) * binWidth) - std::max(lo, -1.0 + k * binWidth);
          power[size_t(k)] += segmentPower * std::max(0.0, overlap) / (hi - lo);
        }
      }
      muStart = muEnd;
    }
  }
  TransferTable table;
  table.density.resize(size_t(bins));
  for (int k = 0; k < bins; ++k)
    table.density[size_t(k)] = power[size_t(k)] / (2.0 * M_PI * binWidth);
  return table;
}

}  // namespace pluvia::optics
