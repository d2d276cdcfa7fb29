#include "rain/drop_glint.h"

#include <algorithm>
#include <cmath>

namespace pluvia::rain {

std::array<float, 2> glintModes(float amplitude20, float amplitude31CosPhi, double cosHalfFromUp) {
  const double x = std::clamp(cosHalfFromUp, -1.0, 1.0);
  const double legendre20 = 0.5 * (3.0 * x * x - 1.0);
  const double legendre31 = 1.5 * (5.0 * x * x - 1.0) * std::sqrt(std::max(0.0, 1.0 - x * x));
  // (n - 1)(n + 2): 4 for mode (2, 0), 10 for mode (3, 1).
  return {float(4.0 * amplitude20 * legendre20), float(10.0 * amplitude31CosPhi * legendre31)};
}

float streakMeanBead(float cycles, float phase, float mode20, float mode31) {
  if (mode20 == 0.0f && mode31 == 0.0f) return 1.0f;
  const double periods = kOscillationModeRatio * std::abs(double(cycles));
  const int samples = int(std::clamp(std::ceil(16.0 * periods), 16.0, 512.0));
  double sum = 0.0;
  for (int i = 0; i < samples; ++i)
    sum += localLightBead(cycles, phase, mode20, mode31, (float(i) + 0.5f) / float(samples));
  return float(sum / samples);
}

float oscillationMeanBead(float mode20, float mode31) {
  // Over every phase the two modes' parabolic sines are independent, each 4 t (1 - t) with t
  // uniform in [0, 1/2] and a random sign. A bead and its opposite (x, -x) average to
  // sqrt(1 + x^2), so the mean is that of (sqrt(1 + (a + b)^2) + sqrt(1 + (a - b)^2)) / 2 over
  // a = mode20 4 t (1 - t), b = mode31 4 u (1 - u): a smooth integrand, which 8 x 8
  // Gauss-Legendre points on [0, 1/2]^2 give to about 1e-7 (once per lit streak and frame).
  constexpr double kNodes[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                0.7966664774136267,  0.9602898564975363};
  constexpr double kWeights[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                  0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                  0.2223810344533745, 0.1012285362903763};
  double sum = 0.0;
  for (int i = 0; i < 8; ++i) {
    const double t = 0.25 * (1.0 + kNodes[i]);
    const double a = mode20 * 4.0 * t * (1.0 - t);
    for (int j = 0; j < 8; ++j) {
      const double u = 0.25 * (1.0 + kNodes[j]);
      const double b = mode31 * 4.0 * u * (1.0 - u);
      sum += kWeights[i] * kWeights[j] * 0.5 *
             (std::sqrt(1.0 + (a + b) * (a + b)) + std::sqrt(1.0 + (a - b) * (a - b)));
    }
  }
  return float(sum / 4.0);  // the weights sum to 2 on each axis
}

void shapeGlint(StreakInstance& streak, const std::array<double, 3>& towardsLight,
                const std::array<double, 3>& towardsCamera, const std::array<double, 3>& up) {
  std::array<double, 3> half{towardsLight[0] + towardsCamera[0], towardsLight[1] + towardsCamera[1],
                             towardsLight[2] + towardsCamera[2]};
  double length = std::sqrt(half[0] * half[0] + half[1] * half[1] + half[2] * half[2]);
  if (!(length > 1e-6)) half = towardsCamera, length = 1.0;
  const double cosHalfFromUp = (half[0] * up[0] + half[1] * up[1] + half[2] * up[2]) / length;
  const auto modes = glintModes(streak.glintMode20, streak.glintMode31, cosHalfFromUp);
  streak.glintMode20 = modes[0];
  streak.glintMode31 = modes[1];
  const float mean = oscillationMeanBead(modes[0], modes[1]);
  streak.localR /= mean;
  streak.localG /= mean;
  streak.localB /= mean;
}

}  // namespace pluvia::rain
