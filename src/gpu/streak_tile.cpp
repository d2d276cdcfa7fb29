#include "gpu/streak_tile.h"

#include <immintrin.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>

#include "gpu/rain_inputs.h"
#include "rain/streak_types.h"

namespace pluvia::gpu {
namespace {

// The span computed per row is widened by this much before the exact per-pixel test, so float
// rounding in the span never drops a pixel the test would keep.
constexpr float kSpanSlackPx = 1e-3f;

// The pixels of row y (inside [xFirst, xLast]) whose centres may lie on the streak; x0 > x1
// when none.
inline void rowSpan(const StreakSetup& s, int y, int xFirst, int xLast, int& x0, int& x1) {
  const float cy = static_cast<float>(y) + 0.5f;
  const float from = std::max(s.lo[0] + s.loSlope[0] * cy, s.lo[1] + s.loSlope[1] * cy);
  const float to = std::min(s.hi[0] + s.hiSlope[0] * cy, s.hi[1] + s.hiSlope[1] * cy);
  // Centre x + 0.5 in [from, to]; clamped in float first (the bounds may be infinite).
  x0 = std::max(xFirst, static_cast<int>(std::max(std::ceil(from - 0.5f - kSpanSlackPx), -1.0f)));
  x1 = std::min(xLast, static_cast<int>(std::min(std::floor(to - 0.5f + kSpanSlackPx), 1.0e9f)));
}

void clearTile(const TileTarget& target, int x0, int y0, int x1, int y1) {
  if (target.cleared) return;
  for (int y = y0; y <= y1; ++y) {
    const size_t first = static_cast<size_t>(y) * target.width + x0;
    const size_t n = static_cast<size_t>(x1 - x0 + 1);
    for (float* plane : {target.r, target.g, target.b, target.a}) {
      std::fill_n(plane + first, n, 0.0f);
    }
  }
}

// One streak, pixel by pixel. The loop has no branch: a pixel outside the quad, behind the
// scene or under a zero matte blends with alpha 0, which leaves it as it was (C is finite:
// validateShading).
void drawStreakPortable(const StreakSetup& s, const PaddedAtlas& atlas, const TileTarget& target,
                        int tx0, int ty0, int tx1, int ty1) {
  const int y0 = std::max(s.y0, ty0), y1 = std::min(s.y1, ty1);
  const int xFirst = std::max(s.x0, tx0), xLast = std::min(s.x1, tx1);
  const float uStep = -s.axisY * s.inverseWidth, vStep = s.axisX * s.inverseLengthPlusWidth;
  const int stride = atlas.stride;
  for (int y = y0; y <= y1; ++y) {
    int x0, x1;
    rowSpan(s, y, xFirst, xLast, x0, x1);
    const float ry = static_cast<float>(y) + 0.5f - s.headY;
    const float rx = static_cast<float>(x0 - s.headPixelX) + s.headOffsetX;
    const float uStart = 0.5f + (rx * -s.axisY + ry * s.axisX) * s.inverseWidth;
    const float vStart = (rx * s.axisX + ry * s.axisY + s.halfWidth) * s.inverseLengthPlusWidth;
    const size_t row = static_cast<size_t>(y) * target.width;
    for (int i = 0; i <= x1 - x0; ++i) {
      const float k = static_cast<float>(i);
      const float u = uStart + k * uStep;
      const float v = vStart + k * vStep;
      const bool inside = u >= 0.0f && u <= 1.0f && v >= 0.0f && v <= 1.0f;
      const size_t pixel = row + static_cast<size_t>(x0 + i);
      const bool inFront =
          !target.depth || !(s.depthMeters > comparableDepthMeters(target.depth[pixel]));
      // Bilinear between texel centres; the border makes every neighbour of a coordinate in
      // the rectangle a valid texel, and outside the quad the coordinates are clamped into it.
      const float tx = s.rectX0 + std::clamp(u, 0.0f, 1.0f) * s.rectWidth;
      const float ty = s.rectY0 + std::clamp(v, 0.0f, 1.0f) * s.rectHeight;
      const float fx0 = std::floor(tx), fy0 = std::floor(ty);
      const float fx = tx - fx0, fy = ty - fy0;
      const float* t =
          atlas.quads + (static_cast<ptrdiff_t>(fy0) * stride + static_cast<ptrdiff_t>(fx0)) * 4;
      const float top = t[0] + fx * (t[1] - t[0]);
      const float bottom = t[2] + fx * (t[3] - t[2]);
      const float matte = top + fy * (bottom - top);
      // clamp(matte * alpha, 0, 1) as the shader; std::max puts NaN at 0.
      const float covered = std::max(0.0f, std::min(matte * s.alpha, 1.0f));
      const float alpha = inside && inFront ? covered : 0.0f;
      const float keep = 1.0f - alpha;
      const float bead = s.hasLocal ? rain::localLightBead(s.beadCycles, s.beadPhase, s.glintMode20,
                                                           s.glintMode31, v)
                                    : 0.0f;
      target.r[pixel] = alpha * (s.radiance[0] + bead * s.local[0]) + target.r[pixel] * keep;
      target.g[pixel] = alpha * (s.radiance[1] + bead * s.local[1]) + target.g[pixel] * keep;
      target.b[pixel] = alpha * (s.radiance[2] + bead * s.local[2]) + target.b[pixel] * keep;
      target.a[pixel] = alpha + target.a[pixel] * keep;
    }
  }
}

// ---- AVX2 + FMA: 8 lanes, 4 pixels of two rows ------------------------------------------------
//
// A streak is walked two rows at a time, over windows of 4 pixels that hold both rows' spans
// (a rain streak is near vertical, so two rows' spans mostly overlap and fit one window). Lanes
// 0-3 are row y, lanes 4-7 row y + 1. A window is kept inside the tile (other threads draw
// the neighbours): at the tile's right edge it is moved left and the lanes already drawn are
// masked off.

#define PLUVIA_AVX2 __attribute__((target("avx2,fma")))

PLUVIA_AVX2 inline __m256 loadRows(const float* rowA, const float* rowB) {
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(rowA)), _mm_loadu_ps(rowB), 1);
}

PLUVIA_AVX2 inline void storeRows(float* rowA, float* rowB, bool second, __m256 value) {
  _mm_storeu_ps(rowA, _mm256_castps256_ps128(value));
  if (second) _mm_storeu_ps(rowB, _mm256_extractf128_ps(value, 1));
}

// layer = alpha * value + layer * keep on the window's two rows.
PLUVIA_AVX2 inline void blendRows(float* rowA, float* rowB, bool second, __m256 alpha, __m256 keep,
                                  __m256 value) {
  const __m256 layer = loadRows(rowA, rowB);
  storeRows(rowA, rowB, second, _mm256_fmadd_ps(layer, keep, _mm256_mul_ps(alpha, value)));
}

// The 2 x 2 neighbourhoods at the 8 offsets (in floats), transposed into the four corners.
PLUVIA_AVX2 inline void loadQuads(const float* quads, const int32_t* offset, __m256& t00,
                                  __m256& t10, __m256& t01, __m256& t11) {
  auto pair = [&](int lane) PLUVIA_AVX2 {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(quads + offset[lane])),
                                _mm_loadu_ps(quads + offset[lane + 4]), 1);
  };
  const __m256 q0 = pair(0), q1 = pair(1), q2 = pair(2), q3 = pair(3);
  // The 4 x 4 transpose of _MM_TRANSPOSE4_PS, in both 128-bit halves at once.
  const __m256 lo01 = _mm256_unpacklo_ps(q0, q1), hi01 = _mm256_unpackhi_ps(q0, q1);
  const __m256 lo23 = _mm256_unpacklo_ps(q2, q3), hi23 = _mm256_unpackhi_ps(q2, q3);
  t00 = _mm256_castpd_ps(_mm256_unpacklo_pd(_mm256_castps_pd(lo01), _mm256_castps_pd(lo23)));
  t10 = _mm256_castpd_ps(_mm256_unpackhi_pd(_mm256_castps_pd(lo01), _mm256_castps_pd(lo23)));
  t01 = _mm256_castpd_ps(_mm256_unpacklo_pd(_mm256_castps_pd(hi01), _mm256_castps_pd(hi23)));
  t11 = _mm256_castpd_ps(_mm256_unpackhi_pd(_mm256_castps_pd(hi01), _mm256_castps_pd(hi23)));
}

// |d| <= FLT_MAX ? d : kFarDepthMeters, for 8 lanes.
PLUVIA_AVX2 inline __m256 comparableDepth8(__m256 depth) {
  const __m256 magnitude = _mm256_andnot_ps(_mm256_set1_ps(-0.0f), depth);
  const __m256 finite = _mm256_cmp_ps(magnitude, _mm256_set1_ps(FLT_MAX), _CMP_LE_OQ);
  return _mm256_blendv_ps(_mm256_set1_ps(kFarDepthMeters), depth, finite);
}

// rain::parabolicSine() for 8 lanes: -4 y (1 - |y|), y = 2 fract(s) - 1.
PLUVIA_AVX2 inline __m256 parabolicSine(__m256 s) {
  const __m256 one = _mm256_set1_ps(1.0f);
  const __m256 fraction = _mm256_sub_ps(s, _mm256_floor_ps(s));
  const __m256 y = _mm256_sub_ps(_mm256_add_ps(fraction, fraction), one);
  const __m256 magnitude = _mm256_andnot_ps(_mm256_set1_ps(-0.0f), y);
  return _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(-4.0f), y), _mm256_sub_ps(one, magnitude));
}

PLUVIA_AVX2 void drawStreakAvx2(const StreakSetup& s, const PaddedAtlas& atlas,
                                const TileTarget& target, int tx0, int ty0, int tx1, int ty1) {
  const int y0 = std::max(s.y0, ty0), y1 = std::min(s.y1, ty1);
  const int xFirst = std::max(s.x0, tx0), xLast = std::min(s.x1, tx1);
  const __m256 laneX = _mm256_setr_ps(0, 1, 2, 3, 0, 1, 2, 3);
  const __m256i laneXi = _mm256_setr_epi32(0, 1, 2, 3, 0, 1, 2, 3);
  const __m256 laneY = _mm256_setr_ps(0, 0, 0, 0, 1, 1, 1, 1);
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
  const __m256 minusAxisY = _mm256_set1_ps(-s.axisY), axisX = _mm256_set1_ps(s.axisX);
  const __m256 axisY = _mm256_set1_ps(s.axisY);
  const __m256 inverseWidth = _mm256_set1_ps(s.inverseWidth);
  const __m256 inverseLength = _mm256_set1_ps(s.inverseLengthPlusWidth);
  const __m256 halfWidth = _mm256_set1_ps(s.halfWidth), half = _mm256_set1_ps(0.5f);
  const __m256 rectX0 = _mm256_set1_ps(s.rectX0), rectY0 = _mm256_set1_ps(s.rectY0);
  const __m256 rectWidth = _mm256_set1_ps(s.rectWidth);
  const __m256 rectHeight = _mm256_set1_ps(s.rectHeight);
  const __m256 streakAlpha = _mm256_set1_ps(s.alpha), streakDepth = _mm256_set1_ps(s.depthMeters);
  const __m256 red = _mm256_set1_ps(s.radiance[0]), green = _mm256_set1_ps(s.radiance[1]);
  const __m256 blue = _mm256_set1_ps(s.radiance[2]);
  const __m256 localRed = _mm256_set1_ps(s.local[0]), localGreen = _mm256_set1_ps(s.local[1]);
  const __m256 localBlue = _mm256_set1_ps(s.local[2]);
  const __m256 beadCycles = _mm256_set1_ps(s.beadCycles), beadPhase = _mm256_set1_ps(s.beadPhase);
  const __m256 glintMode20 = _mm256_set1_ps(s.glintMode20);
  const __m256 glintMode31 = _mm256_set1_ps(s.glintMode31);
  const __m256 modeRatio = _mm256_set1_ps(rain::kOscillationModeRatio);
  const __m256i stride = _mm256_set1_epi32(atlas.stride);
  alignas(32) int32_t quad[8];
  for (int y = y0; y <= y1; y += 2) {
    const bool second = y + 1 <= y1;
    // The centres either row may hold (their hull: a row whose own span is empty only adds
    // lanes the exact test drops), inside [xFirst, xLast].
    const float cyA = static_cast<float>(y) + 0.5f, cyB = second ? cyA + 1.0f : cyA;
    const float from =
        std::min(std::max(s.lo[0] + s.loSlope[0] * cyA, s.lo[1] + s.loSlope[1] * cyA),
                 std::max(s.lo[0] + s.loSlope[0] * cyB, s.lo[1] + s.loSlope[1] * cyB));
    const float to = std::max(std::min(s.hi[0] + s.hiSlope[0] * cyA, s.hi[1] + s.hiSlope[1] * cyA),
                              std::min(s.hi[0] + s.hiSlope[0] * cyB, s.hi[1] + s.hiSlope[1] * cyB));
    const int xs =
        std::max(xFirst, static_cast<int>(std::max(std::ceil(from - 0.5f - kSpanSlackPx), -1.0f)));
    const int xe =
        std::min(xLast, static_cast<int>(std::min(std::floor(to - 0.5f + kSpanSlackPx), 1.0e9f)));
    if (xs > xe) continue;
    // Row B's lanes are live only when it is a row of this streak in the tile.
    const __m256 rowLive = second
                               ? _mm256_castsi256_ps(_mm256_set1_epi32(-1))
                               : _mm256_castsi256_ps(_mm256_setr_epi32(-1, -1, -1, -1, 0, 0, 0, 0));
    const __m256 ry = _mm256_add_ps(_mm256_set1_ps(static_cast<float>(y) + 0.5f - s.headY), laneY);
    const size_t rowA = static_cast<size_t>(y) * target.width;
    const size_t rowB = second ? rowA + static_cast<size_t>(target.width) : rowA;
    for (int x = xs; x <= xe; x += 4) {
      const int wx = std::min(x, tx1 - 3);  // the window's first pixel, inside the tile
      // Lanes left of x were drawn by the window before (or are not on the streak).
      const __m256 fresh = _mm256_castsi256_ps(_mm256_cmpgt_epi32(
          _mm256_add_epi32(_mm256_set1_epi32(wx - x + 1), laneXi), _mm256_setzero_si256()));
      const __m256 rx = _mm256_add_ps(
          _mm256_set1_ps(static_cast<float>(wx - s.headPixelX) + s.headOffsetX), laneX);
      const __m256 across = _mm256_fmadd_ps(ry, axisX, _mm256_mul_ps(rx, minusAxisY));
      const __m256 along = _mm256_fmadd_ps(ry, axisY, _mm256_mul_ps(rx, axisX));
      const __m256 u = _mm256_fmadd_ps(across, inverseWidth, half);
      const __m256 v = _mm256_mul_ps(_mm256_add_ps(along, halfWidth), inverseLength);
      __m256 live = _mm256_and_ps(
          _mm256_and_ps(_mm256_cmp_ps(u, zero, _CMP_GE_OQ), _mm256_cmp_ps(u, one, _CMP_LE_OQ)),
          _mm256_and_ps(_mm256_cmp_ps(v, zero, _CMP_GE_OQ), _mm256_cmp_ps(v, one, _CMP_LE_OQ)));
      live = _mm256_and_ps(live, _mm256_and_ps(fresh, rowLive));
      if (_mm256_testz_ps(live, live)) continue;
      if (target.depth) {
        const __m256 depth =
            comparableDepth8(loadRows(target.depth + rowA + wx, target.depth + rowB + wx));
        live = _mm256_andnot_ps(_mm256_cmp_ps(streakDepth, depth, _CMP_GT_OQ), live);
      }
      // Bilinear between texel centres, as the portable path.
      const __m256 tx =
          _mm256_fmadd_ps(_mm256_min_ps(_mm256_max_ps(u, zero), one), rectWidth, rectX0);
      const __m256 ty =
          _mm256_fmadd_ps(_mm256_min_ps(_mm256_max_ps(v, zero), one), rectHeight, rectY0);
      const __m256 fx0 = _mm256_floor_ps(tx), fy0 = _mm256_floor_ps(ty);
      const __m256 fx = _mm256_sub_ps(tx, fx0), fy = _mm256_sub_ps(ty, fy0);
      const __m256i index = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_cvttps_epi32(fy0), stride),
                                             _mm256_cvttps_epi32(fx0));
      _mm256_store_si256(reinterpret_cast<__m256i*>(quad), _mm256_slli_epi32(index, 2));
      __m256 t00, t10, t01, t11;
      loadQuads(atlas.quads, quad, t00, t10, t01, t11);
      const __m256 top = _mm256_fmadd_ps(fx, _mm256_sub_ps(t10, t00), t00);
      const __m256 bottom = _mm256_fmadd_ps(fx, _mm256_sub_ps(t11, t01), t01);
      const __m256 matte = _mm256_fmadd_ps(fy, _mm256_sub_ps(bottom, top), top);
      // clamp(matte * alpha, 0, 1), NaN to 0 as the portable path: minps returns its second
      // operand when one is NaN, maxps too.
      const __m256 covered =
          _mm256_max_ps(_mm256_min_ps(one, _mm256_mul_ps(matte, streakAlpha)), zero);
      const __m256 alpha = _mm256_and_ps(covered, live);
      const __m256 keep = _mm256_sub_ps(one, alpha);
      const size_t a = rowA + static_cast<size_t>(wx), b = rowB + static_cast<size_t>(wx);
      if (s.hasLocal) {
        // localLightBead() per lane: x = mode20 sin(2 pi s) + mode31 sin(2 pi r s) by
        // parabolicSine(), r = sqrt(1 + x^2) + |x|, bead = x >= 0 ? 1 / r : r.
        const __m256 phase = _mm256_fmadd_ps(beadCycles, v, beadPhase);
        const __m256 x = _mm256_fmadd_ps(
            glintMode20, parabolicSine(phase),
            _mm256_mul_ps(glintMode31, parabolicSine(_mm256_mul_ps(modeRatio, phase))));
        const __m256 r = _mm256_add_ps(_mm256_sqrt_ps(_mm256_fmadd_ps(x, x, one)),
                                       _mm256_andnot_ps(_mm256_set1_ps(-0.0f), x));
        const __m256 bead = _mm256_blendv_ps(r, _mm256_div_ps(one, r),
                                             _mm256_cmp_ps(x, _mm256_setzero_ps(), _CMP_GE_OQ));
        blendRows(target.r + a, target.r + b, second, alpha, keep,
                  _mm256_fmadd_ps(bead, localRed, red));
        blendRows(target.g + a, target.g + b, second, alpha, keep,
                  _mm256_fmadd_ps(bead, localGreen, green));
        blendRows(target.b + a, target.b + b, second, alpha, keep,
                  _mm256_fmadd_ps(bead, localBlue, blue));
      } else {
        blendRows(target.r + a, target.r + b, second, alpha, keep, red);
        blendRows(target.g + a, target.g + b, second, alpha, keep, green);
        blendRows(target.b + a, target.b + b, second, alpha, keep, blue);
      }
      blendRows(target.a + a, target.a + b, second, alpha, keep, one);
    }
  }
}

}  // namespace

namespace detail {

void drawTilePortable(const StreakSetup* streaks, size_t count, const PaddedAtlas& atlas,
                      const TileTarget& target, int x0, int y0, int x1, int y1) {
  clearTile(target, x0, y0, x1, y1);
  for (size_t k = 0; k < count; ++k) drawStreakPortable(streaks[k], atlas, target, x0, y0, x1, y1);
}

void drawTileAvx2(const StreakSetup* streaks, size_t count, const PaddedAtlas& atlas,
                  const TileTarget& target, int x0, int y0, int x1, int y1) {
  clearTile(target, x0, y0, x1, y1);
  for (size_t k = 0; k < count; ++k) drawStreakAvx2(streaks[k], atlas, target, x0, y0, x1, y1);
}

bool cpuHasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return has;
}

}  // namespace detail

void drawTile(const StreakSetup* streaks, size_t count, const PaddedAtlas& atlas,
              const TileTarget& target, int x0, int y0, int x1, int y1, bool portableOnly) {
  if (!portableOnly && detail::cpuHasAvx2() && x1 - x0 + 1 >= 4) {
    detail::drawTileAvx2(streaks, count, atlas, target, x0, y0, x1, y1);
  } else {
    detail::drawTilePortable(streaks, count, atlas, target, x0, y0, x1, y1);
  }
}

}  // namespace pluvia::gpu
