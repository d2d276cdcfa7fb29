#pragma once
// The PRT colour of one streak on the CPU, C = sum_l zonal[l] * sum_m Y_lm(view) * env[l,m],
// clamped to >= 0: the twin of the sum in shaders/rain_stroke.vert (same order of additions).
#include <array>

#include "gpu/rain_renderer.h"

namespace pluvia::gpu {

std::array<float, 3> streakRadiance(const ShadingParams& shading, const StreakInstance& streak);

}  // namespace pluvia::gpu
