#include "gpu/streak_batches.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "gpu/streak_quad.h"

namespace pluvia::gpu {
namespace {

// Line widths of the classes, in pixels. Whole numbers: GL rounds the width of an aliased line
// to the nearest integer. Steps of at most 1.5x, so a streak's line is at most 1.5x (or one
// pixel) wider than it needs. One class more than these: the triangles.
constexpr std::array<float, 12> kClassLineWidthsPx = {1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64};
constexpr int kLineClassCount = static_cast<int>(kClassLineWidthsPx.size());
static_assert(kClassLineWidthsPx.back() == kMaxStreakLineWidthPx);

float classLineWidthPx(int lineClass) {
  return kClassLineWidthsPx[static_cast<size_t>(lineClass)];
}

int widthClass(const rain::StreakInstance& streak) {
  const float needed = lineWidthHolding(streak);
  for (int k = 0; k < kLineClassCount; ++k) {
    if (classLineWidthPx(k) >= needed) return k;
  }
  return kLineClassCount;  // triangles
}

}  // namespace

float lineWidthHolding(const rain::StreakInstance& streak) {
  const StreakQuad quad = StreakQuad::of(streak);
  const float major = std::max(std::abs(quad.axisX), std::abs(quad.axisY));
  // 1e-4 relative: the shader recomputes the axis in its own float operations.
  return streak.widthPx / major * 1.0001f + 2.0f * kCoverageMarginPx;
}

OrderedStreaks orderForDrawing(const std::vector<rain::StreakInstance>& streaks) {
  // A stable counting sort by class: O(n), and instance order within a class.
  std::vector<int> classOf(streaks.size(), -1);
  std::vector<size_t> countOf(kLineClassCount + 1, 0);
  for (size_t i = 0; i < streaks.size(); ++i) {
    if (isInvisible(streaks[i])) continue;
    classOf[i] = widthClass(streaks[i]);
    ++countOf[static_cast<size_t>(classOf[i])];
  }
  OrderedStreaks ordered;
  std::vector<size_t> next(kLineClassCount + 1, 0);
  size_t first = 0;
  for (int k = 0; k <= kLineClassCount; ++k) {
    const size_t count = countOf[static_cast<size_t>(k)];
    next[static_cast<size_t>(k)] = first;
    if (count > 0) {
      ordered.batches.push_back({first, count, k < kLineClassCount ? classLineWidthPx(k) : 0.0f});
    }
    first += count;
  }
  ordered.streaks.resize(first);
  for (size_t i = 0; i < streaks.size(); ++i) {
    if (classOf[i] < 0) continue;
    ordered.streaks[next[static_cast<size_t>(classOf[i])]++] = streaks[i];
  }
  return ordered;
}

}  // namespace pluvia::gpu
