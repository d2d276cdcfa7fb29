#pragma once
// What a frame's local lights give one drop: the rain stage's lit streaks near lamps.
#include <array>
#include <vector>

#include "optics/drop_transfer.h"
#include "optics/local_light.h"

namespace pluvia::optics {

// The radiance the lights give one drop, and the unit direction from the drop to the light that
// gives it most (camera space; zero when none lights it).
struct DropLocalLight {
  std::array<float, 3> rgb{0, 0, 0};
  Vec3 towardsBrightest{0, 0, 0};
};

// The radiance the lights give a drop at `dropMeters` (camera space) seen along unit `view`
// (camera -> drop): sum over lights of D(angle(view, drop -> light)) * I(theta) rgb / d^2 *
// exp(-beta d), d the distance from the drop to the light, at least the bulb's radius.
DropLocalLight dropLocalRadiance(const TransferTable& transfer,
                                 const std::vector<LocalLight>& lights, double betaPerMeter,
                                 const Vec3& dropMeters, const Vec3& view);

}  // namespace pluvia::optics
