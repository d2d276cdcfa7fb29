#include "optics/drop_trace.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pluvia::optics {
namespace {

struct Vec3 {
  double x, y, z;
};

Vec3 operator+(const Vec3& a, const Vec3& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
Vec3 operator*(double s, const Vec3& a) {
  return {s * a.x, s * a.y, s * a.z};
}
double dot(const Vec3& a, const Vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
Vec3 normalised(const Vec3& a) {
  return (1.0 / std::sqrt(dot(a, a))) * a;
}

// splitmix64 (Steele, Lea and Flood 2014): small, deterministic and plenty for jitter.
class Jitter {
 public:
  explicit Jitter(uint64_t seed) : state_(seed) {}
  // Uniform in [0, 1).
  double next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return double(z >> 11) * 0x1.0p-53;
  }

 private:
  uint64_t state_;
};

// The view direction and two unit vectors spanning the drop's disc, perpendicular to it.
struct DiscFrame {
  Vec3 view, e1, e2;
};

DiscFrame discFrame(const Vec3& view) {
  // Crossing with the coordinate axis least aligned with the view keeps the cross product long,
  // whatever the view (the poles included).
  const double ax = std::abs(view.x), ay = std::abs(view.y), az = std::abs(view.z);
  const Vec3 axis = (ax <= ay && ax <= az) ? Vec3{1, 0, 0}
                    : (ay <= az)           ? Vec3{0, 1, 0}
                                           : Vec3{0, 0, 1};
  const Vec3 e1 = normalised(cross(view, axis));
  return {view, e1, cross(view, e1)};
}

// Distance along a unit direction from an origin outside the unit sphere to its near side.
double distanceToEntry(const Vec3& origin, const Vec3& direction) {
  const double halfB = dot(origin, direction);
  const double c = dot(origin, origin) - 1.0;
  // Only rays that hit are traced; near the rim rounding can push the discriminant below 0.
  return -halfB - std::sqrt(std::max(0.0, halfB * halfB - c));
}

// Distance along a unit direction from a point on the sphere, heading inside, to the far side.
double distanceToExit(const Vec3& origin, const Vec3& direction) {
  const double halfB = dot(origin, direction);
  const double c = dot(origin, origin) - 1.0;  // zero up to rounding
  return -halfB + std::sqrt(std::max(0.0, halfB * halfB - c));
}

// A unit direction meeting an interface, split into its reflected and refracted parts.
struct Split {
  double reflectance;  // unpolarised Fresnel, (Rs + Rp) / 2
  Vec3 reflected;
  Vec3 refracted;  // meaningless when reflectance is 1
};

// normal: unit, facing the incoming ray; relativeIndex: index beyond the interface over the
// index before it.
Split splitAtInterface(const Vec3& direction, const Vec3& normal, double relativeIndex) {
  const double cosI = std::clamp(-dot(direction, normal), 0.0, 1.0);
  const Vec3 reflected = direction + (2.0 * cosI) * normal;
  const double sin2T = (1.0 - cosI * cosI) / (relativeIndex * relativeIndex);
  // Total internal reflection cannot happen in a sphere (the exit angle equals the entry angle);
  // the guard keeps rounding from taking the square root of a negative number.
  if (sin2T >= 1.0) return {1.0, reflected, reflected};
  const double cosT = std::sqrt(1.0 - sin2T);
  // Cosine forms: both tend to -1 at grazing incidence, so R -> 1 without dividing by zero.
  const double rs = (cosI - relativeIndex * cosT) / (cosI + relativeIndex * cosT);
  const double rp = (relativeIndex * cosI - cosT) / (relativeIndex * cosI + cosT);
  const double ratio = 1.0 / relativeIndex;
  const Vec3 refracted = ratio * direction + (ratio * cosI - cosT) * normal;
  return {0.5 * (rs * rs + rp * rp), reflected, refracted};
}

Vec3 radiance(const EquirectMap& environment, const Vec3& direction) {
  const std::array<float, 3> l =
      sampleEquirect(environment, float(direction.x), float(direction.y), float(direction.z));
  return {l[0], l[1], l[2]};
}

// The radiance that the camera ray through disc point (b, phi) brings back, summed over every
// part it splits into: the external reflection, then one refracted exit per internal bounce.
Vec3 tracePath(const EquirectMap& environment, const DiscFrame& frame, double eta, double b,
               double phi, const TraceSettings& settings) {
  const Vec3 start =
      -2.0 * frame.view + b * std::cos(phi) * frame.e1 + b * std::sin(phi) * frame.e2;
  Vec3 point = normalised(start + distanceToEntry(start, frame.view) * frame.view);
  const Split entry = splitAtInterface(frame.view, point, eta);
  Vec3 sum = entry.reflectance * radiance(environment, entry.reflected);
  // A path with no power left is over even when minPower is 0.
  const double powerFloor = std::max(settings.minPower, std::numeric_limits<double>::min());
  double power = 1.0 - entry.reflectance;
  Vec3 direction = entry.refracted;
  for (int interaction = 1; power >= powerFloor && interaction < settings.maxInteractions;
       ++interaction) {
    // Back onto the sphere exactly, so rounding cannot build up over many bounces.
    point = normalised(point + distanceToExit(point, direction) * direction);
    const Split exit = splitAtInterface(direction, -1.0 * point, 1.0 / eta);
    const double transmittance = 1.0 - exit.reflectance;
    if (transmittance > 0.0) {
      sum = sum + (power * transmittance) * radiance(environment, exit.refracted);
    }
    power *= exit.reflectance;
    direction = exit.reflected;
  }
  return sum;
}

// Mean of tracePath over a side x side grid, stratified in (b^2, phi) so that it is uniform
// over the disc's area, each cell jittered.
Vec3 meanOverDisc(const EquirectMap& environment, const DiscFrame& frame, double eta, int64_t side,
                  const TraceSettings& settings) {
  Jitter jitter(settings.seed);
  Vec3 sum{0, 0, 0};
  for (int64_t i = 0; i < side; ++i) {
    for (int64_t j = 0; j < side; ++j) {
      const double b2 = (double(i) + jitter.next()) / double(side);
      const double phi = 2.0 * M_PI * (double(j) + jitter.next()) / double(side);
      sum = sum + tracePath(environment, frame, eta, std::sqrt(b2), phi, settings);
    }
  }
  return (1.0 / double(side * side)) * sum;
}

void validate(const EquirectMap& environment, const std::array<double, 3>& eta,
              const TraceSettings& settings) {
  if (environment.empty() ||
      environment.rgb.size() != size_t(environment.width) * size_t(environment.height) * 3) {
    throw std::invalid_argument("traceDropRadiance: empty or malformed environment map");
  }
  for (double e : eta) {
    if (!std::isfinite(e) || e <= 1.0 || e > 3.0) {
      throw std::invalid_argument("traceDropRadiance: refractive index outside (1, 3]");
    }
  }
  if (settings.samples < 1 || settings.maxInteractions < 1 || !(settings.minPower >= 0.0)) {
    throw std::invalid_argument("traceDropRadiance: bad trace settings");
  }
}

Vec3 unitViewDirection(const std::array<double, 3>& viewDirection) {
  const double length = std::hypot(viewDirection[0], viewDirection[1], viewDirection[2]);
  if (!std::isfinite(length) || length == 0.0) {
    throw std::invalid_argument("traceDropRadiance: view direction not finite or zero");
  }
  return (1.0 / length) * Vec3{viewDirection[0], viewDirection[1], viewDirection[2]};
}

}  // namespace

std::array<double, 3> traceDropRadiance(const EquirectMap& environment,
                                        const std::array<double, 3>& viewDirection,
                                        const std::array<double, 3>& eta,
                                        const TraceSettings& settings) {
  validate(environment, eta, settings);
  const DiscFrame frame = discFrame(unitViewDirection(viewDirection));
  const int64_t side = std::max<int64_t>(1, std::llround(std::sqrt(double(settings.samples))));
  if (eta[0] == eta[1] && eta[1] == eta[2]) {
    const Vec3 mean = meanOverDisc(environment, frame, eta[0], side, settings);
    return {mean.x, mean.y, mean.z};
  }
  // Dispersion: one trace per channel, each keeping only its own channel. The same seed gives
  // every channel the same rays, so the noise does not tint the result.
  std::array<double, 3> result{};
  for (int c = 0; c < 3; ++c) {
    const Vec3 mean = meanOverDisc(environment, frame, eta[c], side, settings);
    result[c] = c == 0 ? mean.x : c == 1 ? mean.y : mean.z;
  }
  return result;
}

}  // namespace pluvia::optics
