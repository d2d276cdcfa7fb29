#include "rain/rain_cells.h"

#include <algorithm>
#include <cmath>

#include "util/hash.h"

namespace pluvia::rain {

RainCells::RainCells(const RainCellSettings& settings, Eigen::Vector2d originXZ)
    : settings_(settings), originXZ_(originXZ) {
  settings_.count = std::max(0, settings_.count);
  settings_.radiusMeters = std::max(settings_.radiusMeters, 1e-3);
  settings_.peakDensity = std::max(settings_.peakDensity, 1.0);
  settings_.sizeScale = std::max(settings_.sizeScale, 1.0);
  settings_.regionHalfSizeMeters = std::max(settings_.regionHalfSizeMeters, 0.0);
  for (int k = 0; k < settings_.count; ++k) {
    CounterRng rng(settings_.seed, uint64_t(k));
    const double u = rng.uniform(), v = rng.uniform();
    centers_.push_back(originXZ_ +
                       settings_.regionHalfSizeMeters * Eigen::Vector2d(2 * u - 1, 2 * v - 1));
  }
}

void RainCells::advance(double dtSeconds, const WindField& wind) {
  for (Eigen::Vector2d& c : centers_) {
    const Eigen::Vector3d first = wind.velocityAt(c.x(), c.y());
    const Eigen::Vector2d mid = c + 0.5 * dtSeconds * Eigen::Vector2d(first.x(), first.z());
    const Eigen::Vector3d v = wind.velocityAt(mid.x(), mid.y());
    c += dtSeconds * Eigen::Vector2d(v.x(), v.z());
    wrap(c);
  }
}

void RainCells::translate(const Eigen::Vector2d& displacementMeters) {
  for (Eigen::Vector2d& c : centers_) {
    c += displacementMeters;
    wrap(c);
  }
}

// Into the square around the origin.
void RainCells::wrap(Eigen::Vector2d& centre) const {
  const double side = 2.0 * settings_.regionHalfSizeMeters;
  if (side <= 0.0) return;
  for (int axis = 0; axis < 2; ++axis) {
    const double local = centre[axis] - (originXZ_[axis] - settings_.regionHalfSizeMeters);
    if (local < 0.0 || local >= side)
      centre[axis] = originXZ_[axis] - settings_.regionHalfSizeMeters +
                     (local - side * std::floor(local / side));
  }
}

double RainCells::weightOf(size_t k, double xMeters, double zMeters) const {
  const double dx = xMeters - centers_[k].x(), dz = zMeters - centers_[k].y();
  const double sigma = settings_.radiusMeters;
  return std::exp(-(dx * dx + dz * dz) / (2.0 * sigma * sigma));
}

double RainCells::densityFactor(double xMeters, double zMeters) const {
  double sum = 0.0;
  for (size_t k = 0; k < centers_.size(); ++k) sum += weightOf(k, xMeters, zMeters);
  return 1.0 + (settings_.peakDensity - 1.0) * sum;
}

double RainCells::sizeFactor(double xMeters, double zMeters) const {
  double strongest = 0.0;
  for (size_t k = 0; k < centers_.size(); ++k)
    strongest = std::max(strongest, weightOf(k, xMeters, zMeters));
  return 1.0 + (settings_.sizeScale - 1.0) * strongest;
}

double RainCells::maxDensityFactor() const {
  return 1.0 + settings_.count * (settings_.peakDensity - 1.0);
}

}  // namespace pluvia::rain
