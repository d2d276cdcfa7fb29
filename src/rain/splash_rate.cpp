#include "rain/splash_rate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pluvia::rain {
namespace {

constexpr int kSimpsonIntervals = 4000;  // even
constexpr int kCdfSteps = 1024;

double flux(SizeDistribution d, VelocityModel v, double rate, double diameterMm) {
  return sizeDensityPerMm(d, rate, diameterMm) * terminalVelocity(v, diameterMm);
}

}  // namespace

double sizeDensityPerMm(SizeDistribution distribution, double rate, double diameterMm) {
  if (rate <= 0.0) return 0.0;
  if (distribution == SizeDistribution::MarshallPalmer)
    return kMarshallPalmerN0 * std::exp(-marshallPalmerSlopePerMm(rate) * diameterMm);
  const GammaParameters g = gammaParameters(rate);
  return g.n0 * std::pow(diameterMm, g.mu) * std::exp(-g.slopePerMm * diameterMm);
}

double impactsPerSquareMeterSecond(SizeDistribution distribution, VelocityModel velocity,
                                   double rate, double minMm, double maxMm) {
  if (rate <= 0.0 || maxMm <= minMm) return 0.0;
  if (distribution == SizeDistribution::MarshallPalmer && velocity == VelocityModel::Atlas) {
    const double lambda = marshallPalmerSlopePerMm(rate);
    const double a = std::max(minMm, std::log(10.3 / 9.65) / 0.6), b = maxMm;
    if (b <= a) return 0.0;
    const double l2 = lambda + 0.6;
    return kMarshallPalmerN0 * (9.65 * (std::exp(-lambda * a) - std::exp(-lambda * b)) / lambda -
                                10.3 * (std::exp(-l2 * a) - std::exp(-l2 * b)) / l2);
  }
  const double h = (maxMm - minMm) / kSimpsonIntervals;
  double sum =
      flux(distribution, velocity, rate, minMm) + flux(distribution, velocity, rate, maxMm);
  for (int i = 1; i < kSimpsonIntervals; ++i)
    sum += (i % 2 ? 4.0 : 2.0) * flux(distribution, velocity, rate, minMm + i * h);
  return sum * h / 3.0;
}

ImpactDiameters::ImpactDiameters(SizeDistribution distribution, VelocityModel velocity, double rate,
                                 double minMm, double maxMm)
    : minMm_(minMm), stepMm_((maxMm - minMm) / kCdfSteps), cdf_(kCdfSteps + 1, 0.0) {
  if (!(maxMm > minMm) || rate <= 0.0)
    throw std::invalid_argument("ImpactDiameters: rate > 0 and max > min diameter");
  for (int k = 1; k <= kCdfSteps; ++k) {
    const double a = minMm + (k - 1) * stepMm_, b = a + stepMm_;
    cdf_[size_t(k)] = cdf_[size_t(k) - 1] + 0.5 * stepMm_ *
                                                (flux(distribution, velocity, rate, a) +
                                                 flux(distribution, velocity, rate, b));
  }
  const double total = cdf_.back();
  if (!(total > 0.0)) throw std::invalid_argument("ImpactDiameters: no drop lands");
  for (double& c : cdf_) c /= total;
}

double ImpactDiameters::sampleMm(double u) const {
  const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const size_t k = std::clamp<size_t>(size_t(it - cdf_.begin()), 1, cdf_.size() - 1);
  const double lo = cdf_[k - 1], hi = cdf_[k];
  const double f = hi > lo ? (u - lo) / (hi - lo) : 0.5;
  return minMm_ + (double(k - 1) + std::clamp(f, 0.0, 1.0)) * stepMm_;
}

}  // namespace pluvia::rain
