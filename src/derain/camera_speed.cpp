#include "derain/camera_speed.h"

#include <algorithm>
#include <cmath>

namespace pluvia::derain {

int windowForCameraSpeed(int window, double shiftPerFramePx, int widthPx) {
  if (!(shiftPerFramePx > 0.0)) return window;
  const int halfSpan = int(std::floor(kMaxSpanOfWidth * widthPx / shiftPerFramePx));
  return std::clamp(1 + 2 * halfSpan, 3, window);
}

}  // namespace pluvia::derain
