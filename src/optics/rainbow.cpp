#include "optics/rainbow.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "optics/drop_transfer.h"

namespace pluvia::optics {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kWavelengthMm = 550e-6;

// Box average of `values` over +-halfWidthBins (clamped at the ends), by prefix sums.
std::vector<double> boxSmooth(const std::vector<double>& values, int halfWidthBins) {
  if (halfWidthBins <= 0) return values;
  std::vector<double> prefix(values.size() + 1, 0.0);
  for (size_t i = 0; i < values.size(); ++i) prefix[i + 1] = prefix[i] + values[i];
  std::vector<double> out(values.size());
  const int n = int(values.size());
  for (int i = 0; i < n; ++i) {
    const int a = std::max(0, i - halfWidthBins), b = std::min(n, i + halfWidthBins + 1);
    out[size_t(i)] = (prefix[size_t(b)] - prefix[size_t(a)]) / double(b - a);
  }
  return out;
}

}  // namespace

double descartesScatteringDeg(int k, double eta) {
  if (k < 1 || eta <= 1.0) throw std::invalid_argument("descartesScatteringDeg: k >= 1, eta > 1");
  const double gamma = std::acos(std::sqrt((eta * eta - 1.0) / double(k * k + 2 * k)));
  const double beta = std::asin(std::sin(gamma) / eta);
  double deviation = std::fmod(k * M_PI + 2.0 * gamma - 2.0 * (k + 1) * beta, 2.0 * M_PI);
  if (deviation < 0.0) deviation += 2.0 * M_PI;
  return (deviation > M_PI ? 2.0 * M_PI - deviation : deviation) / kDeg;
}

double RainbowProfile::at(double thetaDeg) const {
  const double x = thetaDeg / binDeg - 0.5;
  const int n = int(density.size());
  if (x <= 0.0) return density.front();
  if (x >= n - 1) return density.back();
  const int i = int(x);
  const double f = x - i;
  return density[size_t(i)] * (1.0 - f) + density[size_t(i) + 1] * f;
}

RainbowProfile rainbowProfile(double eta, const RainbowProfileSettings& s) {
  if (s.binDeg <= 0.0 || s.discSamples < 1000)
    throw std::invalid_argument("rainbowProfile: binDeg > 0 and discSamples >= 1000");
  RainbowProfile profile;
  profile.binDeg = s.binDeg;
  const int bins = int(std::lround(180.0 / s.binDeg));
  std::vector<double> power(size_t(bins), 0.0);
  for (int n : {3, 4}) {
    for (int i = 0; i < s.discSamples; ++i) {
      // Midpoints uniform in b^2 = sin^2(gamma): rays uniform over the disc.
      const double b = std::sqrt((i + 0.5) / s.discSamples);
      const double gamma = std::asin(std::min(b, 1.0 - 1e-12));
      const double theta = std::acos(std::clamp(termCosTheta(n, gamma, eta), -1.0, 1.0)) / kDeg;
      const int bin = std::clamp(int(theta / s.binDeg), 0, bins - 1);
      power[size_t(bin)] += termPower(n, gamma, eta) / s.discSamples;
    }
  }
  profile.density.resize(size_t(bins));
  for (int k = 0; k < bins; ++k) {
    const double solidAngle =
        2.0 * M_PI * (std::cos(k * s.binDeg * kDeg) - std::cos((k + 1) * s.binDeg * kDeg));
    profile.density[size_t(k)] = power[size_t(k)] / solidAngle;
  }
  // The sun's disc and the Airy peak's width, as one box of their summed widths.
  const double airyDeg =
      s.dropDiameterMm > 0.0 ? std::pow(kWavelengthMm / s.dropDiameterMm, 2.0 / 3.0) / kDeg : 0.0;
  const int half = int(std::lround((s.sunRadiusDeg + 0.5 * airyDeg) / s.binDeg));
  profile.density = boxSmooth(profile.density, half);
  return profile;
}

std::array<RainbowProfile, 3> rainbowProfiles(const std::array<double, 3>& eta,
                                              const RainbowProfileSettings& s) {
  return {rainbowProfile(eta[0], s), rainbowProfile(eta[1], s), rainbowProfile(eta[2], s)};
}

}  // namespace pluvia::optics
