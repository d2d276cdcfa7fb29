#include "gpu/streak_raster_cpu.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "gpu/rain_inputs.h"
#include "gpu/streak_quad.h"
#include "gpu/streak_radiance.h"

namespace pluvia::gpu {
namespace {

// The span computed per row is widened by this much before the exact per-pixel test, so float
// rounding in the span never drops a pixel the test would keep.
constexpr float kSpanSlackPx = 1e-3f;

using Setup = StreakRasterCpu::Setup;

// The pixels whose centres may lie on the quad, as in renderRainCpu's candidatePixels(); an
// empty range (x0 > x1) when the quad misses the frame.
void boundingPixels(const StreakQuad& quad, int width, int height, Setup& setup) {
  float minX = INFINITY, minY = INFINITY, maxX = -INFINITY, maxY = -INFINITY;
  for (int s = 0; s < 2; ++s) {
    for (int t = 0; t < 2; ++t) {
      float x, y;
      quad.corner(s, t, 0.0f, x, y);
      minX = std::min(minX, x), maxX = std::max(maxX, x);
      minY = std::min(minY, y), maxY = std::max(maxY, y);
    }
  }
  // Pixel x has its centre at x + 0.5: the centres inside [min, max] are ceil(min - 0.5) ..
  // floor(max - 0.5); one more on each side for rounding.
  auto first = [](float v, int size) {
    return static_cast<int>(std::clamp(std::ceil(v - 0.5f) - 1.0f, 0.0f, static_cast<float>(size)));
  };
  auto last = [](float v, int size) {
    return static_cast<int>(
        std::clamp(std::floor(v - 0.5f) + 1.0f, -1.0f, static_cast<float>(size - 1)));
  };
  setup.x0 = first(minX, width), setup.x1 = last(maxX, width);
  setup.y0 = first(minY, height), setup.y1 = last(maxY, height);
}

// Bounds on the centres cx of a row from lo <= offset + slope * cx + rowSlope * cy <= hi, as
// cx >= lo' + loSlope * cy and cx <= hi' + hiSlope * cy. A slope too small to divide by leaves
// x unbounded: the per-pixel test (and the bounding box) still decide.
void boundCentres(float offset, float slope, float rowSlope, float lo, float hi, Setup& setup,
                  int which) {
  constexpr float kMinSlope = 1e-6f;
  if (std::abs(slope) < kMinSlope) {
    setup.lo[which] = -INFINITY, setup.hi[which] = INFINITY;
    setup.loSlope[which] = setup.hiSlope[which] = 0.0f;
    return;
  }
  const float a = (lo - offset) / slope, b = (hi - offset) / slope, perRow = -rowSlope / slope;
  setup.lo[which] = std::min(a, b), setup.hi[which] = std::max(a, b);
  setup.loSlope[which] = setup.hiSlope[which] = perRow;
}

Setup setupOf(const rain::StreakInstance& streak, const rain::ShadingParams& shading,
              const std::array<float, 4>& rect, int width, int height) {
  const StreakQuad quad = StreakQuad::of(streak);
  Setup setup;
  setup.headPixelX = static_cast<int>(std::floor(quad.headX));
  setup.headOffsetX = static_cast<float>(setup.headPixelX) + 0.5f - quad.headX;
  setup.headY = quad.headY;
  setup.axisX = quad.axisX, setup.axisY = quad.axisY;
  setup.halfWidth = 0.5f * quad.widthPx;
  setup.inverseWidth = 1.0f / quad.widthPx;
  setup.inverseLengthPlusWidth = 1.0f / (quad.lengthPx + quad.widthPx);
  // across = (cx - headX) * -axisY + (cy - headY) * axisX in [-width / 2, width / 2];
  // along = (cx - headX) * axisX + (cy - headY) * axisY in [-width / 2, length + width / 2].
  boundCentres(quad.headX * quad.axisY - quad.headY * quad.axisX, -quad.axisY, quad.axisX,
               -setup.halfWidth, setup.halfWidth, setup, 0);
  boundCentres(-quad.headX * quad.axisX - quad.headY * quad.axisY, quad.axisX, quad.axisY,
               -setup.halfWidth, quad.lengthPx + setup.halfWidth, setup, 1);
  setup.alpha = streak.alpha;
  setup.depthMeters = streak.depthMeters;
  // Texel coordinates with centres on integers, shifted by the one-texel border.
  setup.rectX0 = rect[0] - 0.5f + 1.0f, setup.rectY0 = rect[1] - 0.5f + 1.0f;
  setup.rectWidth = rect[2] - rect[0], setup.rectHeight = rect[3] - rect[1];
  setup.radiance = streakRadiance(shading, streak);
  boundingPixels(quad, width, height, setup);
  return setup;
}

// The scene depth a streak is compared with: as comparableSceneDepth(), every non-finite
// value (sky, NaN) is kFarDepthMeters.
inline float comparableDepth(float depthMeters) {
  return std::abs(depthMeters) <= FLT_MAX ? depthMeters : kFarDepthMeters;
}

struct Layer {
  float* __restrict r;
  float* __restrict g;
  float* __restrict b;
  float* __restrict a;
  const float* depth;  // null: no depth plane
  int width;
};

// Draws one streak into the pixels of [tx0, tx1] x [ty0, ty1] (inclusive). The pixel loop has
// no branch: a pixel outside the quad, behind the scene or under a zero matte blends with
// alpha 0, which leaves it as it was (C is finite: validateShading).
[[gnu::always_inline]] inline void drawInTile(const Setup& s, const float* atlas, int atlasStride,
                                              const Layer& layer, int tx0, int ty0, int tx1,
                                              int ty1) {
  const int y0 = std::max(s.y0, ty0), y1 = std::min(s.y1, ty1);
  const int xFirst = std::max(s.x0, tx0), xLast = std::min(s.x1, tx1);
  // Steps along a row.
  const float uStep = -s.axisY * s.inverseWidth, vStep = s.axisX * s.inverseLengthPlusWidth;
  for (int y = y0; y <= y1; ++y) {
    const float cy = static_cast<float>(y) + 0.5f;
    const float from = std::max(s.lo[0] + s.loSlope[0] * cy, s.lo[1] + s.loSlope[1] * cy);
    const float to = std::min(s.hi[0] + s.hiSlope[0] * cy, s.hi[1] + s.hiSlope[1] * cy);
    // Centre x + 0.5 in [from, to]; clamped in float first (the bounds may be infinite).
    const int x0 =
        std::max(xFirst, static_cast<int>(std::max(std::ceil(from - 0.5f - kSpanSlackPx), -1.0f)));
    const int x1 =
        std::min(xLast, static_cast<int>(std::min(std::floor(to - 0.5f + kSpanSlackPx), 1.0e9f)));
    const float ry = cy - s.headY;
    const float rx = static_cast<float>(x0 - s.headPixelX) + s.headOffsetX;
    const float uStart = 0.5f + (rx * -s.axisY + ry * s.axisX) * s.inverseWidth;
    const float vStart = (rx * s.axisX + ry * s.axisY + s.halfWidth) * s.inverseLengthPlusWidth;
    const size_t row = static_cast<size_t>(y) * layer.width;
    for (int i = 0; i <= x1 - x0; ++i) {
      const float k = static_cast<float>(i);
      const float u = uStart + k * uStep;
      const float v = vStart + k * vStep;
      const bool inside = u >= 0.0f && u <= 1.0f && v >= 0.0f && v <= 1.0f;
      const size_t pixel = row + static_cast<size_t>(x0 + i);
      const bool inFront = !layer.depth || !(s.depthMeters > comparableDepth(layer.depth[pixel]));
      // Bilinear between texel centres; the border makes every neighbour of a texel coordinate
      // in the rectangle a valid texel, and outside the quad the coordinates are clamped to it.
      const float tx = s.rectX0 + std::clamp(u, 0.0f, 1.0f) * s.rectWidth;
      const float ty = s.rectY0 + std::clamp(v, 0.0f, 1.0f) * s.rectHeight;
      const float fx0 = std::floor(tx), fy0 = std::floor(ty);
      const float fx = tx - fx0, fy = ty - fy0;
      const float* t =
          atlas + static_cast<ptrdiff_t>(fy0) * atlasStride + static_cast<ptrdiff_t>(fx0);
      const float top = t[0] + fx * (t[1] - t[0]);
      const float bottom = t[atlasStride] + fx * (t[atlasStride + 1] - t[atlasStride]);
      const float matte = top + fy * (bottom - top);
      // clamp(matte * alpha, 0, 1) as the shader; std::max puts NaN at 0.
      const float covered = std::max(0.0f, std::min(matte * s.alpha, 1.0f));
      const float alpha = inside && inFront ? covered : 0.0f;
      const float keep = 1.0f - alpha;
      layer.r[pixel] = alpha * s.radiance[0] + layer.r[pixel] * keep;
      layer.g[pixel] = alpha * s.radiance[1] + layer.g[pixel] * keep;
      layer.b[pixel] = alpha * s.radiance[2] + layer.b[pixel] * keep;
      layer.a[pixel] = alpha + layer.a[pixel] * keep;
    }
  }
}

// One tile: clears its pixels, then draws its streaks (binned copies, in drawing order). Built
// twice, for x86-64-v3 (AVX2, FMA) and the baseline, the first chosen at load time where the CPU
// has it; the two may differ in the last bit (FMA contracts a * b + c).
__attribute__((target_clones("arch=x86-64-v3", "default"))) void drawTile(
    const Setup* streaks, size_t count, const float* atlas, int atlasStride, const Layer& layer,
    int tx0, int ty0, int tx1, int ty1) {
  for (int y = ty0; y <= ty1; ++y) {
    const size_t first = static_cast<size_t>(y) * layer.width + tx0;
    const size_t n = static_cast<size_t>(tx1 - tx0 + 1);
    for (float* plane : {layer.r, layer.g, layer.b, layer.a}) std::fill_n(plane + first, n, 0.0f);
  }
  for (size_t k = 0; k < count; ++k) {
    drawInTile(streaks[k], atlas, atlasStride, layer, tx0, ty0, tx1, ty1);
  }
}

}  // namespace

void StreakRasterCpu::setStrokeAtlas(const rain::StrokeAtlas& atlas) {
  validateAtlas(atlas);
  paddedWidth_ = atlas.width + 2;
  paddedHeight_ = atlas.height + 2;
  padded_.assign(static_cast<size_t>(paddedWidth_) * paddedHeight_, 0.0f);
  for (int y = 0; y < paddedHeight_; ++y) {
    const int sy = std::clamp(y - 1, 0, atlas.height - 1);
    for (int x = 0; x < paddedWidth_; ++x) {
      const int sx = std::clamp(x - 1, 0, atlas.width - 1);
      padded_[static_cast<size_t>(y) * paddedWidth_ + x] =
          atlas.alpha[static_cast<size_t>(sy) * atlas.width + sx];
    }
  }
  rects_ = atlas.rects;
}

void StreakRasterCpu::render(Image& frame, const std::vector<rain::StreakInstance>& streaks,
                             const rain::ShadingParams& shading) {
  const int width = frame.width, height = frame.height;
  const size_t count = streaks.size();
  setups_.resize(count);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1024), [&](const auto& range) {
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const auto& rect = rects_[static_cast<size_t>(streaks[i].strokeIndex)];
      setups_[i] = setupOf(streaks[i], shading, rect, width, height);
    }
  });

  // Bin the streaks to tiles in drawing order (a counting sort by tile). Each tile gets its own
  // copies: a tile then reads its streaks in sequence instead of hopping over all of them.
  const int tilesX = (width + kTilePx - 1) / kTilePx, tilesY = (height + kTilePx - 1) / kTilePx;
  const size_t tiles = static_cast<size_t>(tilesX) * static_cast<size_t>(tilesY);
  tileStart_.assign(tiles + 1, 0);
  auto forEachTile = [&](const Setup& s, auto&& visit) {
    if (s.x0 > s.x1 || s.y0 > s.y1) return;
    for (int ty = s.y0 / kTilePx; ty <= s.y1 / kTilePx; ++ty) {
      for (int tx = s.x0 / kTilePx; tx <= s.x1 / kTilePx; ++tx) {
        visit(static_cast<size_t>(ty) * tilesX + tx);
      }
    }
  };
  for (const Setup& s : setups_) forEachTile(s, [&](size_t t) { ++tileStart_[t + 1]; });
  for (size_t t = 0; t < tiles; ++t) tileStart_[t + 1] += tileStart_[t];
  binned_.resize(tileStart_[tiles]);
  next_.assign(tileStart_.begin(), tileStart_.end() - 1);
  for (const Setup& s : setups_) forEachTile(s, [&](size_t t) { binned_[next_[t]++] = s; });

  const std::vector<float>* depth = frame.findPlane("depth");
  const Layer layer{frame.plane("rain.R").data(),    frame.plane("rain.G").data(),
                    frame.plane("rain.B").data(),    frame.plane("rain.A").data(),
                    depth ? depth->data() : nullptr, width};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles, 1), [&](const auto& range) {
    for (size_t t = range.begin(); t != range.end(); ++t) {
      const int tx0 = static_cast<int>(t % tilesX) * kTilePx;
      const int ty0 = static_cast<int>(t / tilesX) * kTilePx;
      drawTile(binned_.data() + tileStart_[t], tileStart_[t + 1] - tileStart_[t], padded_.data(),
               paddedWidth_, layer, tx0, ty0, std::min(tx0 + kTilePx, width) - 1,
               std::min(ty0 + kTilePx, height) - 1);
    }
  });
  compositeRainPlanes(shading.backgroundWeight, frame);
}

}  // namespace pluvia::gpu
