#include "rain/stroke_profile.h"

#include <algorithm>

namespace pluvia::rain {

StrokeProfile strokeProfile(const float* alpha, size_t strideFloats, int cols, int rows) {
  StrokeProfile m;
  m.rowPeak.assign(size_t(std::max(rows, 0)), 0.0);
  m.rowSum.assign(size_t(std::max(rows, 0)), 0.0);
  for (int y = 0; y < rows; ++y) {
    const float* p = alpha + size_t(y) * strideFloats;
    for (int x = 0; x < cols; ++x) {
      m.rowPeak[size_t(y)] = std::max(m.rowPeak[size_t(y)], double(p[x]));
      m.rowSum[size_t(y)] += p[x];
    }
    m.contrast = std::max(m.contrast, m.rowPeak[size_t(y)]);
  }
  if (m.contrast <= 0.0) return m;
  m.along = *std::max_element(m.rowSum.begin(), m.rowSum.end());
  const double half = 0.5 * m.along;
  for (int y = 0; y < rows; ++y)
    if (m.rowSum[size_t(y)] >= half) {
      if (m.first < 0) m.first = y;
      m.last = y;
    }
  auto crossing = [&](int inside, int outside) {
    if (outside < 0 || outside >= rows) return 0.5;
    const double a = m.rowSum[size_t(inside)], b = m.rowSum[size_t(outside)];
    return std::clamp((a - half) / std::max(a - b, 1e-12), 0.0, 1.0);
  };
  m.lengthPx =
      double(m.last - m.first) + crossing(m.first, m.first - 1) + crossing(m.last, m.last + 1);
  double widthSum = 0.0;
  int widthRows = 0;
  for (int y = m.first; y <= m.last; ++y) {
    if (m.rowSum[size_t(y)] < half) continue;
    widthSum += m.rowSum[size_t(y)] / m.rowPeak[size_t(y)];
    ++widthRows;
  }
  m.widthPx = widthRows ? widthSum / widthRows : 0.0;
  return m;
}

}  // namespace pluvia::rain
