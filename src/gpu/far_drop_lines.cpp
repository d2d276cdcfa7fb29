#include "gpu/far_drop_lines.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "gpu/rain_inputs.h"
#include "gpu/streak_quad.h"
#include "gpu/streak_radiance.h"
#include "rain/drop_glint.h"
#include "util/parallel.h"

namespace pluvia::gpu {

namespace {

constexpr int kBandRows = 16;  // rows per parallel band

// Blends alpha * C over pixel i of the layer when the streak is in front there.
inline void blend(const LinePlanes& t, size_t i, float alpha, const std::array<float, 3>& c,
                  float depthMeters) {
  if (t.depth && depthMeters > comparableDepthMeters(t.depth[i])) return;
  const float keep = 1.0f - alpha;
  t.r[i] = alpha * c[0] + keep * t.r[i];
  t.g[i] = alpha * c[1] + keep * t.g[i];
  t.b[i] = alpha * c[2] + keep * t.b[i];
  t.a[i] = alpha + keep * t.a[i];
}

}  // namespace

void FarDropLines::setStrokeMeans(const rain::StrokeAtlas& atlas) {
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

void FarDropLines::draw(const std::vector<rain::StreakInstance>& streaks,
                        const rain::ShadingParams& shading, const LinePlanes& target) {
  lines_.resize(streaks.size());
  forEachIndex(streaks.size(), [&](size_t k) {
    const rain::StreakInstance& s = streaks[k];
    Line& line = lines_[k];
    line.first = 0, line.last = -1;
    if (isInvisible(s)) return;
    const StreakQuad quad = StreakQuad::of(s);
    const float half = 0.5f * quad.widthPx, span = quad.lengthPx + quad.widthPx;
    const float ax = quad.headX - quad.axisX * half, ay = quad.headY - quad.axisY * half;
    const float bx = ax + quad.axisX * span, by = ay + quad.axisY * span;
    line.steep = std::abs(quad.axisY) >= std::abs(quad.axisX);
    // Major (m) and minor (n) coordinates of the ends, ordered along the major axis.
    float m0 = line.steep ? ay : ax, m1 = line.steep ? by : bx;
    float n0 = line.steep ? ax : ay, n1 = line.steep ? bx : by;
    if (m0 > m1) std::swap(m0, m1), std::swap(n0, n1);
    const int extent = line.steep ? target.height : target.width;
    // Centres c + 0.5 in [m0, m1]; a line shorter than a pixel gets one sample at its middle.
    int first = static_cast<int>(std::ceil(m0 - 0.5f)),
        last = static_cast<int>(std::floor(m1 - 0.5f));
    const int samples = std::max(1, last - first + 1);
    if (first > last) first = last = static_cast<int>(std::floor(0.5f * (m0 + m1)));
    line.slope = m1 - m0 > 1e-6f ? (n1 - n0) / (m1 - m0) : 0.0f;
    line.minor0 = n0, line.major0 = m0;
    const float mass = std::min(s.alpha, 1.0f) * strokeMeans_[static_cast<size_t>(s.strokeIndex)] *
                       quad.widthPx * span;
    line.alphaPerSample = mass / static_cast<float>(samples);
    line.first = std::max(first, 0), line.last = std::min(last, extent - 1);
    line.depthMeters = s.depthMeters;
    line.color = streakRadiance(shading, s);
    // The beaded local term's mean over the streak: a far streak is a line of one colour.
    const float bead =
        s.localR > 0.0f || s.localG > 0.0f || s.localB > 0.0f
            ? rain::streakMeanBead(s.beadCycles, s.beadPhase, s.glintMode20, s.glintMode31)
            : 0.0f;
    line.color[0] += bead * s.localR, line.color[1] += bead * s.localG;
    line.color[2] += bead * s.localB;
  });

  // Lines by bands of rows, binned in order (a counting sort): every pixel is blended by the
  // one thread drawing its band, in the streaks' order.
  const int bands = (target.height + kBandRows - 1) / kBandRows;
  auto bandsOf = [&](const Line& line, int& from, int& to) {
    // A flat line's rows are unknown before its samples: every band may hold some.
    from = line.steep ? line.first / kBandRows : 0;
    to = line.steep ? line.last / kBandRows : bands - 1;
    if (line.first > line.last) from = 1, to = 0;
  };
  bandStart_.assign(static_cast<size_t>(bands) + 1, 0);
  for (const Line& line : lines_) {
    int from, to;
    bandsOf(line, from, to);
    for (int band = from; band <= to; ++band) ++bandStart_[static_cast<size_t>(band) + 1];
  }
  for (int band = 0; band < bands; ++band) bandStart_[band + 1] += bandStart_[band];
  binned_.resize(bandStart_.back());
  bandNext_.assign(bandStart_.begin(), bandStart_.end() - 1);
  for (uint32_t k = 0; k < lines_.size(); ++k) {
    int from, to;
    bandsOf(lines_[k], from, to);
    for (int band = from; band <= to; ++band) binned_[bandNext_[band]++] = k;
  }
  forEachIndex(bands, [&](int band) {
    const int rowFirst = band * kBandRows;
    const int rowLast = std::min(target.height, rowFirst + kBandRows) - 1;
    for (size_t j = bandStart_[band]; j < bandStart_[band + 1]; ++j) {
      const Line& line = lines_[binned_[j]];
      if (line.steep) {
        const int y0 = std::max(line.first, rowFirst), y1 = std::min(line.last, rowLast);
        for (int y = y0; y <= y1; ++y) {
          // The sample's x, and its split between the two pixels whose centres straddle it.
          const float x =
              line.minor0 + line.slope * (static_cast<float>(y) + 0.5f - line.major0) - 0.5f;
          const float fx = std::floor(x);
          const float right = x - fx;
          const int px = static_cast<int>(fx);
          const size_t row = static_cast<size_t>(y) * target.width;
          if (px >= 0 && px < target.width) {
            blend(target, row + px, std::min(1.0f, line.alphaPerSample * (1.0f - right)),
                  line.color, line.depthMeters);
          }
          if (px + 1 >= 0 && px + 1 < target.width) {
            blend(target, row + px + 1, std::min(1.0f, line.alphaPerSample * right), line.color,
                  line.depthMeters);
          }
        }
      } else {
        // Columns [first, last]; a sample's y decides whether its pixels lie in this band.
        for (int x = line.first; x <= line.last; ++x) {
          const float y =
              line.minor0 + line.slope * (static_cast<float>(x) + 0.5f - line.major0) - 0.5f;
          const float fy = std::floor(y);
          const float lower = y - fy;
          const int py = static_cast<int>(fy);
          if (py >= rowFirst && py <= rowLast && py < target.height) {
            blend(target, static_cast<size_t>(py) * target.width + x,
                  std::min(1.0f, line.alphaPerSample * (1.0f - lower)), line.color,
                  line.depthMeters);
          }
          if (py + 1 >= rowFirst && py + 1 <= rowLast && py + 1 < target.height) {
            blend(target, static_cast<size_t>(py + 1) * target.width + x,
                  std::min(1.0f, line.alphaPerSample * lower), line.color, line.depthMeters);
          }
        }
      }
    }
  });
}

}  // namespace pluvia::gpu
