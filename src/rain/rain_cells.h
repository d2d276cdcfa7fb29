#pragma once
// Local high-density rain (Mizukami et al. section 4.1): Gaussian cells on the XZ plane where
// drops are denser and larger, each centre carried by the wind like a particle.
//
// Centres start uniformly in a square around an origin and wrap around within that square as
// the wind carries them (as drops wrap in their box), so a shot never runs out of cells; the
// square should exceed the visible ground by a few radii to hide the wrap.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "rain/wind_field.h"

namespace pluvia::rain {

struct RainCellSettings {
  int count = 0;
  double radiusMeters = 10.0;  // Gaussian sigma
  double peakDensity = 4.0;    // density multiplier at a centre, >= 1
  double sizeScale = 1.3;      // drop size multiplier at a centre, >= 1
  double regionHalfSizeMeters = 50.0;
  uint64_t seed = 1;
};

class RainCells {
 public:
  RainCells(const RainCellSettings& settings, Eigen::Vector2d originXZ);

  // Moves every centre with the wind at its position (midpoint rule, exact in a uniform wind).
  void advance(double dtSeconds, const WindField& wind);
  // Carries every centre by the same displacement (a closed-form drift over a long time).
  void translate(const Eigen::Vector2d& displacementMeters);

  // 1 + sum_k (peak - 1) exp(-r_k^2 / (2 sigma^2)).
  double densityFactor(double xMeters, double zMeters) const;
  // 1 + (scale - 1) max_k exp(-r_k^2 / (2 sigma^2)): 1 away from cells, the scale at a centre.
  double sizeFactor(double xMeters, double zMeters) const;
  // Bound of densityFactor everywhere and at every time (cells may meet): 1 + count (peak - 1).
  double maxDensityFactor() const;

  const std::vector<Eigen::Vector2d>& centersXZ() const { return centers_; }

 private:
  void wrap(Eigen::Vector2d& centre) const;
  double weightOf(size_t k, double xMeters, double zMeters) const;

  RainCellSettings settings_;
  Eigen::Vector2d originXZ_;
  std::vector<Eigen::Vector2d> centers_;
};

}  // namespace pluvia::rain
