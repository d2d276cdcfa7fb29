// The Preetham clear sky, the CIE overcast sky and a uniform sky fitted to seen sky radiance
// (sky_model.h).
#include "envmap/sky_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "image/luminance.h"
#include "util/parallel.h"

namespace pluvia::envmap {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
// Preetham's fit holds for turbidity 2..10 or so; 1.7 is the clearest sky the paper plots.
constexpr double kMinTurbidity = 1.7, kMaxTurbidity = 10.0;
// Views at the horizon: 1 / cos theta is capped (the Perez gradient term is then its limit).
constexpr double kMinCosTheta = 0.01;

double dot(const Vec3& a, const Vec3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

Vec3 fromElevationAzimuth(double elevation, double azimuth) {
  // Azimuth 0 looks along -Z, positive to +X (the report's convention).
  return {std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
          -std::cos(elevation) * std::cos(azimuth)};
}

// CIE XYZ to linear Rec.709 (D65).
Vec3 xyzToRec709(double x, double y, double z) {
  return {3.2404542 * x - 1.5371385 * y - 0.4985314 * z,
          -0.9692660 * x + 1.8760108 * y + 0.0415560 * z,
          0.0556434 * x - 0.2040259 * y + 1.0572252 * z};
}

// One Preetham sky: the coefficients and the zenith values (divided by F(0, theta_s)) for a
// turbidity and sun, so each view costs three Perez evaluations.
class PreethamSky {
 public:
  PreethamSky(double t, const Vec3& sun)
      : sun_(sun),
        kY_(preethamLuminanceCoefficients(t)),
        kx_(preethamXCoefficients(t)),
        ky_(preethamYCoefficients(t)) {
    const double sunZenith = std::acos(std::clamp(sun[1], -1.0, 1.0));
    const auto zenith = preethamZenithChromaticity(t, sunZenith);
    luminance_ = preethamZenithLuminance(t, sunZenith) / perez(kY_, 0.0, sunZenith);
    x_ = zenith[0] / perez(kx_, 0.0, sunZenith);
    y_ = zenith[1] / perez(ky_, 0.0, sunZenith);
  }
  Vec3 rgb(const Vec3& view) const {
    const double theta = std::acos(std::clamp(view[1], kMinCosTheta, 1.0));
    const double gamma = std::acos(std::clamp(dot(sun_, view), -1.0, 1.0));
    const double luminance = luminance_ * perez(kY_, theta, gamma);
    const double x = x_ * perez(kx_, theta, gamma);
    const double y = y_ * perez(ky_, theta, gamma);
    const double big = luminance / std::max(y, 1e-6);
    Vec3 out = xyzToRec709(x * big, luminance, (1.0 - x - y) * big);
    // The conversion can leave a channel slightly negative for saturated chromaticities.
    for (double& c : out) c = std::max(c, 1e-4 * std::abs(luminance));
    return out;
  }

 private:
  Vec3 sun_;
  PerezCoefficients kY_, kx_, ky_;
  double luminance_ = 0.0, x_ = 0.0, y_ = 0.0;
};

// The model's shape along each sample for one parameter set, then the per-channel log scale and
// residual in closed form.
struct LogSamples {
  std::vector<Vec3> direction;
  std::vector<std::array<double, 3>> logRgb;
  std::vector<double> weight;
  double weightSum = 0.0;
};

template <typename Shape>
SkyFit fitScale(const LogSamples& s, SkyFit fit, Shape shape) {
  std::array<double, 3> mean{0, 0, 0}, square{0, 0, 0};
  for (size_t i = 0; i < s.direction.size(); ++i) {
    const std::array<double, 3> m = shape(s.direction[i]);
    for (size_t c = 0; c < 3; ++c) {
      const double r = s.logRgb[i][c] - std::log(std::max(m[c], 1e-30));
      mean[c] += s.weight[i] * r;
      square[c] += s.weight[i] * r * r;
    }
  }
  double residual = 0.0;
  for (size_t c = 0; c < 3; ++c) {
    mean[c] /= s.weightSum;
    residual += std::max(0.0, square[c] / s.weightSum - mean[c] * mean[c]) / 3.0;
    fit.scale[c] = std::exp(mean[c]);
  }
  fit.residual = std::sqrt(residual);
  return fit;
}

std::array<double, 3> shapeOf(const SkyFit& fit, const Vec3& view) {
  switch (fit.kind) {
    case SkyKind::Preetham: {
      const Vec3 rgb = PreethamSky(fit.turbidity, fit.sun).rgb(view);
      if (fit.grey) {
        const double y = rec709Luminance(rgb);
        return {y, y, y};
      }
      return {rgb[0], rgb[1], rgb[2]};
    }
    case SkyKind::CieOvercast: {
      const double f = cieOvercastShape(view);
      return {f, f, f};
    }
    case SkyKind::Uniform:
      break;
  }
  return {1, 1, 1};
}

SkyFit fitPreetham(const LogSamples& s, const std::optional<Vec3>& knownSun) {
  SkyFit start;
  start.kind = SkyKind::Preetham;
  auto evaluate = [&](double turbidity, double elevation, double azimuth) {
    SkyFit fit = start;
    fit.turbidity = turbidity;
    fit.sun = knownSun ? *knownSun : fromElevationAzimuth(elevation, azimuth);
    const PreethamSky sky(turbidity, fit.sun);
    const SkyFit colour = fitScale(s, fit, [&](const Vec3& v) {
      const Vec3 rgb = sky.rgb(v);
      return std::array<double, 3>{rgb[0], rgb[1], rgb[2]};
    });
    // The luminance distribution with one colour: a hazy or white-balanced sky whose colour does
    // not follow Preetham's chromaticity across the dome.
    fit.grey = true;
    const SkyFit grey = fitScale(s, fit, [&](const Vec3& v) {
      const double y = rec709Luminance(sky.rgb(v));
      return std::array<double, 3>{y, y, y};
    });
    return grey.residual < colour.residual ? grey : colour;
  };
  const std::vector<double> turbidities = {1.7, 2.0, 2.5, 3.0, 4.0, 5.0, 6.5, 8.0, 10.0};
  std::vector<double> elevations = {2, 8, 15, 25, 35, 45, 60, 75, 88};
  std::vector<double> azimuths;
  for (int a = 0; a < 24; ++a) azimuths.push_back(a * 15.0);
  if (knownSun) elevations = {0}, azimuths = {0};
  // Coarse grid, one task per azimuth.
  std::vector<SkyFit> best(azimuths.size());
  forEachIndex(azimuths.size(), [&](size_t a) {
    best[a].residual = std::numeric_limits<double>::infinity();
    for (double t : turbidities)
      for (double e : elevations) {
        const SkyFit f = evaluate(t, e * kDeg, azimuths[a] * kDeg);
        if (f.residual < best[a].residual) best[a] = f;
      }
  });
  SkyFit fit = *std::min_element(best.begin(), best.end(), [](const SkyFit& a, const SkyFit& b) {
    return a.residual < b.residual;
  });
  // Refinement: coordinate steps on turbidity, elevation and azimuth, halved when none helps.
  double t = fit.turbidity;
  double e = std::asin(std::clamp(fit.sun[1], -1.0, 1.0));
  double a = std::atan2(fit.sun[0], -fit.sun[2]);
  double stepT = 0.5, stepAngle = 4.0 * kDeg;
  for (int iteration = 0; iteration < 60 && stepT > 0.02; ++iteration) {
    bool improved = false;
    for (int k = 0; k < (knownSun ? 2 : 6); ++k) {
      double nt = t, ne = e, na = a;
      const double sign = k % 2 ? -1.0 : 1.0;
      if (k / 2 == 0) nt = std::clamp(t + sign * stepT, kMinTurbidity, kMaxTurbidity);
      if (k / 2 == 1) ne = std::clamp(e + sign * stepAngle, 0.0, 89.5 * kDeg);
      if (k / 2 == 2) na = a + sign * stepAngle;
      const SkyFit f = evaluate(nt, ne, na);
      if (f.residual < fit.residual - 1e-9) {
        fit = f, t = nt, e = ne, a = na;
        improved = true;
      }
    }
    if (!improved) stepT *= 0.5, stepAngle *= 0.5;
  }
  return fit;
}

}  // namespace

PerezCoefficients preethamLuminanceCoefficients(double t) {
  return {0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251, 0.1206 * t - 2.5771,
          -0.0670 * t + 0.3703};
}

PerezCoefficients preethamXCoefficients(double t) {
  return {-0.0193 * t - 0.2592, -0.0665 * t + 0.0008, -0.0004 * t + 0.2125, -0.0641 * t - 0.8989,
          -0.0033 * t + 0.0452};
}

PerezCoefficients preethamYCoefficients(double t) {
  return {-0.0167 * t - 0.2608, -0.0950 * t + 0.0092, -0.0079 * t + 0.2102, -0.0441 * t - 1.6537,
          -0.0109 * t + 0.0529};
}

double perez(const PerezCoefficients& k, double theta, double gamma) {
  const double cosTheta = std::max(std::cos(theta), kMinCosTheta);
  const double cosGamma = std::cos(gamma);
  return (1.0 + k.a * std::exp(k.b / cosTheta)) *
         (1.0 + k.c * std::exp(k.d * gamma) + k.e * cosGamma * cosGamma);
}

double preethamZenithLuminance(double t, double sunZenith) {
  const double chi = (4.0 / 9.0 - t / 120.0) * (kPi - 2.0 * sunZenith);
  return (4.0453 * t - 4.9710) * std::tan(chi) - 0.2155 * t + 2.4192;
}

std::array<double, 2> preethamZenithChromaticity(double t, double sunZenith) {
  const double s1 = sunZenith, s2 = s1 * s1, s3 = s2 * s1;
  const double t2 = t * t;
  const double x = t2 * (0.00166 * s3 - 0.00375 * s2 + 0.00209 * s1) +
                   t * (-0.02903 * s3 + 0.06377 * s2 - 0.03202 * s1 + 0.00394) +
                   (0.11693 * s3 - 0.21196 * s2 + 0.06052 * s1 + 0.25886);
  const double y = t2 * (0.00275 * s3 - 0.00610 * s2 + 0.00317 * s1) +
                   t * (-0.04214 * s3 + 0.08970 * s2 - 0.04153 * s1 + 0.00516) +
                   (0.15346 * s3 - 0.26756 * s2 + 0.06670 * s1 + 0.26688);
  return {x, y};
}

Vec3 preethamRgb(double t, const Vec3& sun, const Vec3& view) {
  return PreethamSky(t, sun).rgb(view);
}

double cieOvercastShape(const Vec3& view) {
  return (1.0 + 2.0 * std::max(view[1], 0.0)) / 3.0;
}

std::string SkyFit::describe() const {
  switch (kind) {
    case SkyKind::Preetham:
      return fmt::format("preetham{} T {:.1f}, sun at {:.0f}° elevation {:.0f}° azimuth",
                         grey ? " (luminance, one colour)" : "", turbidity,
                         std::asin(std::clamp(sun[1], -1.0, 1.0)) / kDeg,
                         std::atan2(sun[0], -sun[2]) / kDeg);
    case SkyKind::CieOvercast:
      return "cie overcast";
    case SkyKind::Uniform:
      break;
  }
  return "uniform sky";
}

std::optional<SkyFit> fitSky(const std::vector<SkySample>& samples,
                             const SkyFitSettings& settings) {
  LogSamples s;
  // A floor for log: far below anything a camera records next to this sky.
  double mean = 0.0, total = 0.0;
  auto usable = [](const SkySample& sample) {  // a NaN or infinity from a bad file is no sky
    return sample.weight > 0.0 && sample.direction[1] > 0.0 && std::isfinite(sample.rgb[0]) &&
           std::isfinite(sample.rgb[1]) && std::isfinite(sample.rgb[2]);
  };
  for (const SkySample& sample : samples) {
    if (!usable(sample)) continue;
    mean += sample.weight * (sample.rgb[0] + sample.rgb[1] + sample.rgb[2]) / 3.0;
    total += sample.weight;
  }
  if (!(total > 0.0) || !(mean > 0.0)) return std::nullopt;
  const double floor = 1e-4 * mean / total;
  for (const SkySample& sample : samples) {
    if (!usable(sample)) continue;
    s.direction.push_back(sample.direction);
    std::array<double, 3> logRgb;
    for (size_t c = 0; c < 3; ++c) logRgb[c] = std::log(std::max(double(sample.rgb[c]), floor));
    s.logRgb.push_back(logRgb);
    s.weight.push_back(sample.weight);
    s.weightSum += sample.weight;
  }
  if (s.direction.empty()) return std::nullopt;
  SkyFit uniform;
  uniform.kind = SkyKind::Uniform;
  uniform = fitScale(s, uniform, [](const Vec3&) { return std::array<double, 3>{1, 1, 1}; });
  SkyFit overcast;
  overcast.kind = SkyKind::CieOvercast;
  overcast = fitScale(s, overcast, [](const Vec3& v) {
    const double f = cieOvercastShape(v);
    return std::array<double, 3>{f, f, f};
  });
  SkyFit best = overcast.residual < uniform.residual ? overcast : uniform;
  if (settings.preetham) {
    const SkyFit clear = fitPreetham(s, settings.sun);
    if (clear.residual < best.residual) best = clear;
  }
  return best;
}

std::array<double, 3> evaluateSky(const SkyFit& fit, const Vec3& view) {
  Vec3 v = view;
  if (v[1] < 0.0) {  // below the horizon: the horizon in that azimuth
    const double h = std::hypot(v[0], v[2]);
    v = h > 0 ? Vec3{v[0] / h, 0.0, v[2] / h} : Vec3{1, 0, 0};
  }
  const std::array<double, 3> shape = shapeOf(fit, v);
  return {fit.scale[0] * shape[0], fit.scale[1] * shape[1], fit.scale[2] * shape[2]};
}

std::array<double, 3> skyIrradiance(const SkyFit& fit) {
  constexpr int kRows = 45, kColumns = 90;  // 2° x 4° cells
  std::array<double, 3> e{0, 0, 0};
  for (int i = 0; i < kRows; ++i) {
    const double theta0 = 0.5 * kPi * i / kRows, theta1 = 0.5 * kPi * (i + 1) / kRows;
    const double theta = 0.5 * (theta0 + theta1);
    // Integral of cos theta d omega over the cell: pi (sin^2 theta1 - sin^2 theta0) / columns.
    const double weight =
        kPi * (std::pow(std::sin(theta1), 2) - std::pow(std::sin(theta0), 2)) / kColumns;
    for (int j = 0; j < kColumns; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / kColumns;
      const Vec3 v{std::sin(theta) * std::sin(phi), std::cos(theta),
                   -std::sin(theta) * std::cos(phi)};
      const auto l = evaluateSky(fit, v);
      for (size_t c = 0; c < 3; ++c) e[c] += weight * l[c];
    }
  }
  return e;
}

}  // namespace pluvia::envmap
