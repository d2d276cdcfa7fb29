#include "optics/single_scattering.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace pluvia::optics {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kHalfPi = kPi / 2;
// exp(-60) ~ 1e-26: a path attenuated more than this adds nothing even from a 1e6 lamp.
constexpr double kMaxOpticalDepth = 60.0;
// Below this 1 - cos A the cone's cos(theta) part cancels against its constant part in the
// tables (a 1e-4 table error times 1 / (1 - cos A)); a thin cone is integrated by quadrature.
constexpr double kThinConeOneMinusCos = 0.03;

double dot(const Vec3& a, const Vec3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec3& a) {
  return std::sqrt(dot(a, a));
}

// Adaptive Simpson to a tolerance, depth-limited.
double simpsonStep(const std::function<double(double)>& f, double a, double b, double fa, double fm,
                   double fb, double whole, double tolerance, int depth) {
  const double m = 0.5 * (a + b);
  const double lm = 0.5 * (a + m);
  const double rm = 0.5 * (m + b);
  const double flm = f(lm);
  const double frm = f(rm);
  const double left = (m - a) / 6 * (fa + 4 * flm + fm);
  const double right = (b - m) / 6 * (fm + 4 * frm + fb);
  if (depth <= 0 || std::abs(left + right - whole) <= 15 * tolerance)
    return left + right + (left + right - whole) / 15;
  return simpsonStep(f, a, m, fa, flm, fm, left, tolerance / 2, depth - 1) +
         simpsonStep(f, m, b, fm, frm, fb, right, tolerance / 2, depth - 1);
}

double integrate(const std::function<double(double)>& f, double a, double b, double tolerance) {
  if (b <= a) return 0.0;
  const double fa = f(a);
  const double fb = f(b);
  const double fm = f(0.5 * (a + b));
  const double whole = (b - a) / 6 * (fa + 4 * fm + fb);
  return simpsonStep(f, a, b, fa, fm, fb, whole, tolerance, 40);
}

double factor(ScatteringIntegral which, double e) {
  switch (which) {
    case ScatteringIntegral::S:
      return std::sin(2 * e);
    case ScatteringIntegral::C:
      return std::cos(2 * e);
    default:
      return 1.0;
  }
}

// 24-point Gauss-Legendre on [a, b] (nodes and weights on [-1, 1], positive half).
double gaussLegendre(const std::function<double(double)>& f, double a, double b) {
  static constexpr double x[12] = {0.0640568928626056, 0.1911188674736163, 0.3150426796961634,
                                   0.4337935076260451, 0.5454214713888396, 0.6480936519369755,
                                   0.7401241915785544, 0.8200019859739029, 0.8864155270044011,
                                   0.9382745520027328, 0.9747285559713095, 0.9951872199970213};
  static constexpr double w[12] = {0.1279381953467522, 0.1258374563468283, 0.1216704729278034,
                                   0.1155056680537256, 0.1074442701159656, 0.0976186521041139,
                                   0.0861901615319533, 0.0733464814110803, 0.0592985849154368,
                                   0.0442774388174198, 0.0285313886289337, 0.0123412297999872};
  const double c = 0.5 * (a + b);
  const double r = 0.5 * (b - a);
  double sum = 0.0;
  for (int i = 0; i < 12; ++i) sum += w[i] * (f(c - r * x[i]) + f(c + r * x[i]));
  return sum * r;
}

// The light as the ray sees it: a ray passing closer to the centre than the bulb's radius hits
// the bulb, whose own glow is the lamp's picture, not the medium's; it is taken as passing at
// the radius (the light moved away from the ray), which keeps h > 0 and both methods alike.
Vec3 apparentPosition(const LocalLight& light, const Vec3& ray) {
  const Vec3& s = light.positionMeters;
  const double along = std::max(dot(ray, s), 0.0);  // the ray starts at the camera
  Vec3 across{s[0] - along * ray[0], s[1] - along * ray[1], s[2] - along * ray[2]};
  const double distance = norm(across);
  if (distance >= light.radiusMeters) return s;
  if (distance < 1e-12) {  // through the centre: any direction across the ray
    const Vec3 other = std::abs(ray[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    across = cross(ray, other);
  }
  const double n = norm(across);
  return {along * ray[0] + across[0] / n * light.radiusMeters,
          along * ray[1] + across[1] / n * light.radiusMeters,
          along * ray[2] + across[2] / n * light.radiusMeters};
}

bool insideCone(const LocalLight& light, const Vec3& ray, double x) {
  if (!light.spot) return true;
  const Vec3 w{x * ray[0] - light.positionMeters[0], x * ray[1] - light.positionMeters[1],
               x * ray[2] - light.positionMeters[2]};
  return dot(w, light.axis) >= light.cosHalfAngle * norm(w);
}

}  // namespace

namespace {
// scatteringIntegral to an absolute tolerance on the scaled integrand.
double scatteringIntegralTo(ScatteringIntegral which, double u, double e0, double e1,
                            double logScale, double tolerance) {
  e0 = std::clamp(e0, 0.0, kHalfPi);
  e1 = std::clamp(e1, 0.0, kHalfPi);
  if (e1 <= e0) return 0.0;
  // Fold exp(-u tan e0) into the scale; the integrand then falls from O(1) over
  // e - e0 ~ cos^2(e0) / u: cut there so that no first sample misses it.
  const double shift = e0 < kHalfPi ? u * std::tan(e0) : 0.0;
  auto g = [&](double e) {
    if (e >= kHalfPi) return 0.0;
    return std::exp(shift - u * std::tan(e)) * factor(which, e);
  };
  std::vector<double> cuts{e0, e1};
  if (u > 0) {
    const double width = std::cos(e0) * std::cos(e0) / u;
    for (double k : {0.25, 1.0, 4.0, 16.0, 64.0})
      if (e0 + k * width < e1) cuts.push_back(e0 + k * width);
  }
  std::sort(cuts.begin(), cuts.end());
  double sum = 0.0;
  for (size_t i = 1; i < cuts.size(); ++i) sum += integrate(g, cuts[i - 1], cuts[i], tolerance);
  return std::exp(logScale - shift) * sum;
}
}  // namespace

double scatteringIntegral(ScatteringIntegral which, double u, double e0, double e1,
                          double logScale) {
  return scatteringIntegralTo(which, u, e0, e1, logScale, 1e-14);
}

ScatteringTables::ScatteringTables(int aSamples, int vSamples)
    : aSamples_(std::max(2, aSamples)), vSamples_(std::max(2, vSamples)) {
  const size_t size = static_cast<size_t>(aSamples_) * static_cast<size_t>(vSamples_);
  f_.assign(size, 0.0);
  s_.assign(size, 0.0);
  c_.assign(size, 0.0);
  for (int i = 0; i < aSamples_; ++i) {
    const double a = double(i) / (aSamples_ - 1);
    const size_t row = static_cast<size_t>(i) * static_cast<size_t>(vSamples_);
    for (int j = 0; j + 1 < vSamples_; ++j) {  // the last column, v = pi/2, stays 0
      const double v = kHalfPi * j / (vSamples_ - 1);
      const size_t at = row + static_cast<size_t>(j);
      if (i == aSamples_ - 1) {
        // u = infinity: the integrand lives in e - v ~ cos^2(v) / u, where it is the factor
        // at v times exp(-u sec^2(v) (e - v)).
        const double width = std::cos(v) * std::cos(v);
        f_[at] = width;
        s_[at] = std::sin(2 * v) * width;
        c_[at] = std::cos(2 * v) * width;
        continue;
      }
      const double u = a / (1.0 - a);
      // exp(u tan v) folded in: the complementary integral from v, scaled by (1 + u).
      const double logScale = std::log1p(u) + u * std::tan(v);
      // The tables' own error is the bilinear lookup's (about 1e-3 of these O(1) values): a
      // 1e-9 quadrature is ample, and builds them in a fraction of the time 1e-14 takes.
      f_[at] = scatteringIntegralTo(ScatteringIntegral::F, u, v, kHalfPi, logScale, 1e-9);
      s_[at] = scatteringIntegralTo(ScatteringIntegral::S, u, v, kHalfPi, logScale, 1e-9);
      c_[at] = scatteringIntegralTo(ScatteringIntegral::C, u, v, kHalfPi, logScale, 1e-9);
    }
  }
}

double ScatteringTables::lookup(const std::vector<double>& table, double u, double v) const {
  const double a = std::isinf(u) ? 1.0 : u / (1.0 + u);
  const double x = std::clamp(a, 0.0, 1.0) * (aSamples_ - 1);
  const double y = std::clamp(v / kHalfPi, 0.0, 1.0) * (vSamples_ - 1);
  const int x0 = std::min(int(x), aSamples_ - 2);
  const int y0 = std::min(int(y), vSamples_ - 2);
  const double fx = x - x0;
  const double fy = y - y0;
  auto at = [&](int i, int j) {
    return table[static_cast<size_t>(i) * static_cast<size_t>(vSamples_) + static_cast<size_t>(j)];
  };
  return (1 - fx) * ((1 - fy) * at(x0, y0) + fy * at(x0, y0 + 1)) +
         fx * ((1 - fy) * at(x0 + 1, y0) + fy * at(x0 + 1, y0 + 1));
}

double ScatteringTables::integral(ScatteringIntegral which, double u, double e0, double e1,
                                  double logScale) const {
  e0 = std::clamp(e0, 0.0, kHalfPi);
  e1 = std::clamp(e1, 0.0, kHalfPi);
  if (e1 <= e0) return 0.0;
  const std::vector<double>& table =
      which == ScatteringIntegral::F ? f_ : (which == ScatteringIntegral::S ? s_ : c_);
  // exp(logScale - u tan e) G(u, e) / (1 + u) at each end; 0 at e = pi/2.
  auto end = [&](double e) {
    if (e >= kHalfPi) return 0.0;
    return std::exp(logScale - u * std::tan(e) - std::log1p(u)) * lookup(table, u, e);
  };
  return end(e0) - end(e1);
}

double ScatteringTables::integralFromSlopes(double u, double t0, double t1, double logScale) const {
  if (!(t1 > t0)) return 0.0;
  const double logNorm = logScale - std::log1p(u);
  // exp(logScale - u tan e) G(u, e) / (1 + u) at the end of slope t; 0 at t = +inf (e = pi/2).
  auto end = [&](double t) {
    if (!std::isfinite(t)) return t > 0 ? 0.0 : NAN;
    const double root = std::sqrt(1.0 + t * t);
    // t + root loses its digits for t << 0: the same as 1 / (root - t).
    const double tanE = t >= 0.0 ? t + root : 1.0 / (root - t);
    return std::exp(logNorm - u * tanE) * lookup(f_, u, kPi / 4 + 0.5 * std::atan(t));
  };
  return end(t0) - end(t1);
}

std::vector<std::array<double, 2>> litIntervals(const LocalLight& light, const Vec3& ray,
                                                double rayLengthMeters, double betaPerMeter) {
  // Beyond |s| + 60 / beta the light's path is attenuated below exp(-60): the ray ends there.
  const double far =
      std::min(rayLengthMeters, norm(light.positionMeters) + kMaxOpticalDepth / betaPerMeter);
  if (!(far > 0)) return {};
  if (!light.spot) return {{0.0, far}};
  // Where the ray crosses the cone's surface or the plane through the apex across the axis:
  // between two such points it is wholly inside or wholly outside.
  const Vec3& s = light.positionMeters;
  const Vec3& a = light.axis;
  const double ra = dot(ray, a), sa = dot(s, a), rs = dot(ray, s), ss = dot(s, s);
  const double c2 = light.cosHalfAngle * light.cosHalfAngle;
  std::vector<double> cuts{0.0, far};
  // (x ra - sa)^2 - c^2 (x^2 - 2 x rs + ss) = 0
  const double qa = ra * ra - c2, qb = 2 * (c2 * rs - ra * sa), qc = sa * sa - c2 * ss;
  if (std::abs(qa) > 1e-14) {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc >= 0) {
      const double root = std::sqrt(disc);
      const double q = -0.5 * (qb + std::copysign(root, qb));
      cuts.push_back(q / qa);
      if (q != 0) cuts.push_back(qc / q);
    }
  } else if (std::abs(qb) > 1e-14) {
    cuts.push_back(-qc / qb);
  }
  if (std::abs(ra) > 1e-14) cuts.push_back(sa / ra);
  std::vector<double> inside;
  for (double x : cuts)
    if (std::isfinite(x) && x >= 0 && x <= far) inside.push_back(x);
  std::sort(inside.begin(), inside.end());
  std::vector<std::array<double, 2>> lit;
  for (size_t i = 1; i < inside.size(); ++i) {
    const double x0 = inside[i - 1], x1 = inside[i];
    if (x1 - x0 <= 0 || !insideCone(light, ray, 0.5 * (x0 + x1))) continue;
    if (!lit.empty() && lit.back()[1] == x0)
      lit.back()[1] = x1;
    else
      lit.push_back({x0, x1});
  }
  return lit;
}

double inscatteredRadiance(const ScatteringTables& tables, const LocalLight& given, const Vec3& ray,
                           double rayLengthMeters, double betaPerMeter) {
  if (!(betaPerMeter > 0)) return 0.0;
  LocalLight light = given;
  light.positionMeters = apparentPosition(given, ray);
  const Vec3& s = light.positionMeters;
  const double T = betaPerMeter * norm(s);
  // d + x >= |s| on every path: all of it is attenuated at least by exp(-T).
  if (T > kMaxOpticalDepth) return 0.0;
  const double tCos = betaPerMeter * dot(ray, s);       // T cos(gamma)
  const double h = betaPerMeter * norm(cross(ray, s));  // T sin(gamma), > 0
  auto epsilonAt = [&](double x) {
    return kPi / 4 + 0.5 * std::atan((betaPerMeter * x - tCos) / h);
  };
  const double beta2 = betaPerMeter * betaPerMeter;
  if (!light.spot && tCos >= 0) {
    // A point light ahead: one interval, its ends as slopes (no interval list, no tangent).
    const double far = std::min(rayLengthMeters, norm(s) + kMaxOpticalDepth / betaPerMeter);
    if (!(far > 0)) return 0.0;
    const double radiance =
        beta2 / (2 * kPi * h) *
        tables.integralFromSlopes(h, -tCos / h, (betaPerMeter * far - tCos) / h, -tCos);
    return std::isfinite(radiance) ? std::max(radiance, 0.0) : 0.0;
  }
  const double oneMinusCosA = 1.0 - light.cosHalfAngle;
  double radiance = 0.0;
  for (const auto& [x0, x1] : litIntervals(light, ray, rayLengthMeters, betaPerMeter)) {
    // The ray's end beyond the light (litIntervals) is past exp(-60): its e < pi/2 loses nothing.
    const double e0 = epsilonAt(x0);
    const double e1 = epsilonAt(x1);
    auto integral = [&](ScatteringIntegral which) {
      return tables.integral(which, h, e0, e1, -tCos);
    };
    if (!light.spot && tCos >= 0) {
      radiance += beta2 / (2 * kPi * h) * integral(ScatteringIntegral::F);
    } else if (tCos < 0 || oneMinusCosA < kThinConeOneMinusCos) {
      // A light behind the ray's start (gamma > 90 deg: e lives in a sliver below pi/2 of width
      // ~ h / T, finer than a table cell) or a thin cone: by quadrature in e of I(theta) times
      // exp(-T cos gamma - h tan e).
      auto integrand = [&](double e) {
        if (e >= kHalfPi) return 0.0;
        const double x = (tCos + h * std::tan(2 * e - kHalfPi)) / betaPerMeter;
        const Vec3 w{x * ray[0] - s[0], x * ray[1] - s[1], x * ray[2] - s[2]};
        const double d = norm(w);
        const Vec3 direction = d > 0 ? Vec3{w[0] / d, w[1] / d, w[2] / d} : light.axis;
        return spotFactor(light, dot(direction, light.axis)) * std::exp(-tCos - h * std::tan(e));
      };
      radiance += beta2 / (2 * kPi * h) * gaussLegendre(integrand, e0, e1);
    } else {
      // I = I0 (constant + slope cos theta) inside the cone.
      const double constant =
          light.falloffQ - (1.0 - light.falloffQ) * light.cosHalfAngle / oneMinusCosA;
      const double slope = (1.0 - light.falloffQ) / oneMinusCosA;
      const double ra = dot(ray, light.axis);
      const double sigmaA = betaPerMeter * dot(s, light.axis);
      radiance += constant * beta2 / (2 * kPi * h) * integral(ScatteringIntegral::F) +
                  slope * beta2 / (2 * kPi * h * h) *
                      ((ra * tCos - sigmaA) * integral(ScatteringIntegral::S) -
                       ra * h * integral(ScatteringIntegral::C));
    }
  }
  return std::isfinite(radiance) ? std::max(radiance, 0.0) : 0.0;
}

double inscatteredRadianceReference(const LocalLight& given, const Vec3& ray,
                                    double rayLengthMeters, double betaPerMeter) {
  if (!(betaPerMeter > 0)) return 0.0;
  LocalLight light = given;
  light.positionMeters = apparentPosition(given, ray);
  const Vec3& s = light.positionMeters;
  auto integrand = [&](double x) {
    const Vec3 w{x * ray[0] - s[0], x * ray[1] - s[1], x * ray[2] - s[2]};
    const double d = norm(w);
    const Vec3 direction = Vec3{w[0] / d, w[1] / d, w[2] / d};
    return betaPerMeter / (4 * kPi) * spotFactor(light, dot(direction, light.axis)) *
           std::exp(-betaPerMeter * (d + x)) / (d * d);
  };
  const double nearest = dot(ray, s);
  const double width = norm(cross(ray, s));
  double radiance = 0.0;
  for (const auto& [x0, x1] : litIntervals(light, ray, rayLengthMeters, betaPerMeter)) {
    // Split where the integrand peaks (the point nearest the light), a few widths around it,
    // and along its fall-off (the light's distance and the mean free path), so that no first
    // samples of a part can all miss what it holds.
    std::vector<double> cuts{x0, x1};
    std::vector<double> marks;
    for (double k : {-8.0, -2.0, 0.0, 2.0, 8.0}) marks.push_back(nearest + k * width);
    for (double k : {0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0}) {
      marks.push_back(k * norm(s));
      marks.push_back(k / betaPerMeter);
    }
    for (double x : marks)
      if (x > x0 && x < x1) cuts.push_back(x);
    std::sort(cuts.begin(), cuts.end());
    for (size_t i = 1; i < cuts.size(); ++i)
      radiance += integrate(integrand, cuts[i - 1], cuts[i], 1e-16);
  }
  return radiance;
}

}  // namespace pluvia::optics
