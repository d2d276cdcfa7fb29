#pragma once
// The colour C of one streak on the CPU, the twin of streakRadiance() in
// shaders/rain_stroke.vert (same terms, same order of additions):
//   C = max(sum_l zonal[l] * sum_m Y_lm(view) * env[l,m], 0)   when shading.envSh is set
//     + sampleEquirect(radianceMap, view)                      when shading.radianceMap is set
#include <array>

#include "rain/streak_types.h"

namespace pluvia::gpu {

std::array<float, 3> streakRadiance(const rain::ShadingParams& shading,
                                    const rain::StreakInstance& streak);

}  // namespace pluvia::gpu
