#include "gpu/far_drop_layer.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "gpu/rain_inputs.h"
#include "gpu/streak_quad.h"
#include "gpu/streak_radiance.h"

namespace pluvia::gpu {
namespace {

constexpr int kCellFloats = 5;  // r, g, b, a, depth
constexpr int kSumDoubles = 5;  // mass, mass * r, g, b, mass * depth

// Cell index and weight of the next cell for position p (pixels) on an axis of `cells` cells:
// cell centres at (i + 0.5) * kCellPx, clamped at the edges.
struct AxisWeights {
  int first, second;
  float secondWeight;
};

inline AxisWeights axisWeights(float p, int cells) {
  const float f = p / static_cast<float>(FarDropLayer::kCellPx) - 0.5f;
  const float floorF = std::floor(f);
  const int i = static_cast<int>(floorF);
  return {std::clamp(i, 0, cells - 1), std::clamp(i + 1, 0, cells - 1), f - floorF};
}

}  // namespace

void FarDropLayer::setStrokeMeans(const rain::StrokeAtlas& atlas) {
  strokeMeans_.clear();
  for (const auto& rect : atlas.rects) {
    const int x0 = static_cast<int>(rect[0]), y0 = static_cast<int>(rect[1]);
    const int x1 = static_cast<int>(rect[2]), y1 = static_cast<int>(rect[3]);
    double sum = 0.0;
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) sum += atlas.alpha[static_cast<size_t>(y) * atlas.width + x];
    }
    const double texels = std::max(1.0, static_cast<double>(x1 - x0) * (y1 - y0));
    strokeMeans_.push_back(static_cast<float>(sum / texels));
  }
}

void FarDropLayer::build(int width, int height, const std::vector<rain::StreakInstance>& streaks,
                         const rain::ShadingParams& shading, const float* sceneDepth) {
  width_ = width, height_ = height;
  cellsX_ = (width + kCellPx - 1) / kCellPx;
  cellsY_ = (height + kCellPx - 1) / kCellPx;
  const size_t cells = static_cast<size_t>(cellsX_) * static_cast<size_t>(cellsY_);
  sums_.assign(cells * kSumDoubles, 0.0);
  empty_ = true;
  for (const rain::StreakInstance& streak : streaks) {
    if (isInvisible(streak)) continue;
    const float dx = streak.tailX - streak.headX, dy = streak.tailY - streak.headY;
    const float length = std::sqrt(dx * dx + dy * dy);
    const auto stroke = static_cast<size_t>(streak.strokeIndex);
    const double mass = static_cast<double>(std::min(streak.alpha, 1.0f)) * strokeMeans_[stroke] *
                        streak.widthPx * (length + streak.widthPx);
    std::array<float, 3> radiance = streakRadiance(shading, streak);
    // localLightBead() averages 1 + kBeadDepth / 3 over its period.
    const float bead = 1.0f + rain::kBeadDepth / 3.0f;
    radiance[0] += bead * streak.localR;
    radiance[1] += bead * streak.localG;
    radiance[2] += bead * streak.localB;
    const int points = 1 + static_cast<int>(length / static_cast<float>(kCellPx));
    const double pointMass = mass / points;
    for (int k = 0; k < points; ++k) {
      const float t = (static_cast<float>(k) + 0.5f) / static_cast<float>(points);
      const float x = streak.headX + t * dx, y = streak.headY + t * dy;
      // Off the frame the quad draws nothing either.
      if (!(x >= 0.0f && y >= 0.0f && x < static_cast<float>(width) &&
            y < static_cast<float>(height))) {
        continue;
      }
      if (sceneDepth) {
        const size_t pixel =
            static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
        if (streak.depthMeters > comparableDepthMeters(sceneDepth[pixel])) continue;
      }
      const AxisWeights wx = axisWeights(x, cellsX_), wy = axisWeights(y, cellsY_);
      const int columns[2] = {wx.first, wx.second}, rows[2] = {wy.first, wy.second};
      const double weightsX[2] = {1.0 - wx.secondWeight, wx.secondWeight};
      const double weightsY[2] = {1.0 - wy.secondWeight, wy.secondWeight};
      for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 2; ++i) {
          const double m = pointMass * weightsX[i] * weightsY[j];
          double* sum =
              sums_.data() + (static_cast<size_t>(rows[j]) * cellsX_ + columns[i]) * kSumDoubles;
          sum[0] += m;
          sum[1] += m * radiance[0];
          sum[2] += m * radiance[1];
          sum[3] += m * radiance[2];
          sum[4] += m * streak.depthMeters;
        }
      }
      empty_ = false;
    }
  }
  cells_.assign(cells * kCellFloats, 0.0f);
  const double cellArea = static_cast<double>(kCellPx) * kCellPx;
  for (size_t c = 0; c < cells; ++c) {
    const double* sum = sums_.data() + c * kSumDoubles;
    float* cell = cells_.data() + c * kCellFloats;
    cell[4] = kFarDepthMeters;  // an empty cell is transparent: its depth does not matter
    if (!(sum[0] > 0.0)) continue;
    const double coverage = 1.0 - std::exp(-sum[0] / cellArea);
    for (int k = 0; k < 3; ++k) cell[k] = static_cast<float>(coverage * sum[1 + k] / sum[0]);
    cell[3] = static_cast<float>(coverage);
    cell[4] = static_cast<float>(sum[4] / sum[0]);
  }
}

void FarDropLayer::row(int y, int x0, int x1, const float* depthRow, float* r, float* g, float* b,
                       float* a) const {
  const AxisWeights wy = axisWeights(static_cast<float>(y) + 0.5f, cellsY_);
  const float* rowA = cells_.data() + static_cast<size_t>(wy.first) * cellsX_ * kCellFloats;
  const float* rowB = cells_.data() + static_cast<size_t>(wy.second) * cellsX_ * kCellFloats;
  const float bottom = wy.secondWeight, top = 1.0f - bottom;
  // Pixels between two cell centres share their four corners: walk the row in such spans.
  int x = x0;
  while (x <= x1) {
    const AxisWeights wx = axisWeights(static_cast<float>(x) + 0.5f, cellsX_);
    // Centres between cell centres i and i + 1, (i + 0.5) kCellPx <= x + 0.5 < (i + 1.5)
    // kCellPx, are pixels i kCellPx + kCellPx / 2 to i kCellPx + 3 kCellPx / 2 - 1.
    const int cell = static_cast<int>(
        std::floor((static_cast<float>(x) + 0.5f) / static_cast<float>(kCellPx) - 0.5f));
    const int last = std::min(x1, cell * kCellPx + 3 * kCellPx / 2 - 1);
    const float* corner[4] = {rowA + wx.first * kCellFloats, rowA + wx.second * kCellFloats,
                              rowB + wx.first * kCellFloats, rowB + wx.second * kCellFloats};
    const int n = last - x + 1, i0 = x - x0;
    if (corner[0][3] == 0.0f && corner[1][3] == 0.0f && corner[2][3] == 0.0f &&
        corner[3][3] == 0.0f) {
      std::fill_n(r + i0, n, 0.0f), std::fill_n(g + i0, n, 0.0f);
      std::fill_n(b + i0, n, 0.0f), std::fill_n(a + i0, n, 0.0f);
      x = last + 1;
      continue;
    }
    // Every corner in front of the whole span (no depth plane, or the scene farther than the
    // farthest corner throughout): the masks are all 1, a plain bilinear blend.
    float sceneNearest = INFINITY;
    if (depthRow) {
      for (int k = x; k <= last; ++k) {
        sceneNearest = std::min(sceneNearest, comparableDepthMeters(depthRow[k]));
      }
    }
    const float cornerFarthest =
        std::max(std::max(corner[0][4], corner[1][4]), std::max(corner[2][4], corner[3][4]));
    const bool allInFront = !depthRow || cornerFarthest <= sceneNearest;
    float left[4], right[4];
    for (int c = 0; c < 4; ++c) {
      left[c] = top * corner[0][c] + bottom * corner[2][c];
      right[c] = top * corner[1][c] + bottom * corner[3][c];
    }
    for (int k = x; k <= last; ++k) {
      const float fx = static_cast<float>(k) + 0.5f;
      const float f = fx / static_cast<float>(kCellPx) - 0.5f;
      const float w = wx.first == wx.second ? 0.0f : f - std::floor(f);
      float out[4];
      if (allInFront) {
        for (int c = 0; c < 4; ++c) out[c] = left[c] + w * (right[c] - left[c]);
      } else {
        const float scene = comparableDepthMeters(depthRow[k]);
        const float weight[4] = {corner[0][4] > scene ? 0.0f : (1.0f - w) * top,
                                 corner[1][4] > scene ? 0.0f : w * top,
                                 corner[2][4] > scene ? 0.0f : (1.0f - w) * bottom,
                                 corner[3][4] > scene ? 0.0f : w * bottom};
        for (int c = 0; c < 4; ++c) {
          out[c] = weight[0] * corner[0][c] + weight[1] * corner[1][c] + weight[2] * corner[2][c] +
                   weight[3] * corner[3][c];
        }
      }
      const int i = k - x0;
      r[i] = out[0], g[i] = out[1], b[i] = out[2], a[i] = out[3];
    }
    x = last + 1;
  }
}

void FarDropLayer::underlay(const float* sceneDepth, std::vector<float>& rgba) const {
  if (empty_) return;
  std::vector<float> veil(static_cast<size_t>(width_) * 4);
  float* r = veil.data();
  float* g = r + width_;
  float* b = g + width_;
  float* a = b + width_;
  for (int y = 0; y < height_; ++y) {
    const size_t first = static_cast<size_t>(y) * width_;
    row(y, 0, width_ - 1, sceneDepth ? sceneDepth + first : nullptr, r, g, b, a);
    for (int x = 0; x < width_; ++x) {
      float* pixel = rgba.data() + (first + x) * 4;
      const float keep = 1.0f - pixel[3];
      pixel[0] += keep * r[x];
      pixel[1] += keep * g[x];
      pixel[2] += keep * b[x];
      pixel[3] += keep * a[x];
    }
  }
}

}  // namespace pluvia::gpu
