#pragma once
// The screen-space quad of one streak and its matte coordinates, on the CPU. The vertex and
// fragment shaders (shaders/rain_stroke.vert, .frag) compute the same frame with the same
// float operations; renderRainCpu() relies on that to match the GPU pixel for pixel.
#include <algorithm>
#include <cmath>

#include "rain/streak_types.h"

namespace pluvia::gpu {

// Below this length a streak is a still drop: its axis is taken as vertical, (0, 1), so it is
// drawn as a widthPx x widthPx square (the header's rule for head == tail).
inline constexpr float kDegenerateStreakLengthPx = 1e-4f;

struct StreakQuad {
  float headX = 0, headY = 0;  // pixels, y down
  float axisX = 0, axisY = 1;  // unit vector head -> tail
  float lengthPx = 0;          // head to tail
  float widthPx = 0;

  static StreakQuad of(const rain::StreakInstance& streak) {
    StreakQuad quad;
    quad.headX = streak.headX;
    quad.headY = streak.headY;
    quad.widthPx = streak.widthPx;
    const float dx = streak.tailX - streak.headX;
    const float dy = streak.tailY - streak.headY;
    const float length = std::sqrt(dx * dx + dy * dy);
    if (length > kDegenerateStreakLengthPx) {
      quad.axisX = dx / length;
      quad.axisY = dy / length;
      quad.lengthPx = length;
    }
    return quad;
  }

  // Matte coordinates of the image point (x, y): u across, 0 at the left edge seen from head
  // to tail (on screen, y down), 1 at the right edge; v along, 0 at the head end (head - axis *
  // width / 2), 1 at the tail end (tail + axis * width / 2). The point lies on the streak when
  // both are in [0, 1].
  void matteCoordinates(float x, float y, float& u, float& v) const {
    const float relX = x - headX;
    const float relY = y - headY;
    const float across = relX * -axisY + relY * axisX;
    const float along = relX * axisX + relY * axisY;
    u = 0.5f + across / widthPx;
    v = (along + 0.5f * widthPx) / (lengthPx + widthPx);
  }

  // Corner of the quad grown by marginPx on every side; s = 0/1 left/right, t = 0/1 head/tail.
  void corner(int s, int t, float marginPx, float& x, float& y) const {
    const float halfWidth = 0.5f * widthPx + marginPx;
    const float along = t == 0 ? -halfWidth : lengthPx + halfWidth;
    const float across = s == 0 ? -halfWidth : halfWidth;
    x = headX + axisX * along - axisY * across;
    y = headY + axisY * along + axisX * across;
  }

  // The axis-aligned box of the quad's four corners.
  void bounds(float& minX, float& minY, float& maxX, float& maxY) const {
    minX = minY = INFINITY;
    maxX = maxY = -INFINITY;
    for (int s = 0; s < 2; ++s) {
      for (int t = 0; t < 2; ++t) {
        float x, y;
        corner(s, t, 0.0f, x, y);
        minX = std::min(minX, x), maxX = std::max(maxX, x);
        minY = std::min(minY, y), maxY = std::max(maxY, y);
      }
    }
  }
};

// A streak that cannot cover any pixel: zero (or NaN) width or alpha. Both renderers skip it.
inline bool isInvisible(const rain::StreakInstance& streak) {
  return !(streak.widthPx > 0.0f) || !(streak.alpha > 0.0f);
}

}  // namespace pluvia::gpu
