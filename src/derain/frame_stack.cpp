#include "derain/frame_stack.h"

#include <cmath>

namespace pluvia::derain {

cv::Vec2d streakDirection(double angleDeg) {
  const double a = angleDeg * M_PI / 180.0;
  return {std::sin(a), -std::cos(a)};
}

double foldRainAngleDeg(double angleDeg) {
  double a = std::fmod(angleDeg, 180.0);
  if (a <= -90.0) a += 180.0;
  if (a > 90.0) a -= 180.0;
  return a;
}

}  // namespace pluvia::derain
