#include "gpu/streak_radiance.h"

#include <algorithm>

namespace pluvia::gpu {
namespace {

// The SH (PRT) term, clamped to >= 0.
std::array<float, 3> shRadiance(const rain::ShadingParams& shading,
                                const rain::StreakInstance& streak) {
  const std::array<float, 16> basis = rain::shEvaluate(streak.viewX, streak.viewY, streak.viewZ);
  std::array<float, 3> radiance{0.0f, 0.0f, 0.0f};
  for (int l = 0; l <= shading.shOrder; ++l) {
    std::array<float, 3> band{0.0f, 0.0f, 0.0f};
    for (int m = -l; m <= l; ++m) {
      const int index = l * l + l + m;
      for (int c = 0; c < 3; ++c) band[c] += basis[index] * shading.envSh[index][c];
    }
    for (int c = 0; c < 3; ++c) radiance[c] += shading.transferZonal[l] * band[c];
  }
  for (float& channel : radiance) channel = std::max(channel, 0.0f);
  return radiance;
}

}  // namespace

std::array<float, 3> streakRadiance(const rain::ShadingParams& shading,
                                    const rain::StreakInstance& streak) {
  std::array<float, 3> radiance{0.0f, 0.0f, 0.0f};
  if (!shading.envSh.empty()) radiance = shRadiance(shading, streak);
  if (!shading.radianceMap.empty()) {
    const std::array<float, 3> map =
        sampleEquirect(shading.radianceMap, streak.viewX, streak.viewY, streak.viewZ);
    for (int c = 0; c < 3; ++c) radiance[c] += map[c];
  }
  return radiance;
}

}  // namespace pluvia::gpu
