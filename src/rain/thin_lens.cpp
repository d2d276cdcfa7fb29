#include "rain/thin_lens.h"

#include <algorithm>
#include <cmath>

namespace pluvia::rain {

ThinLens ThinLens::of(double focalPx, int widthPx, double sensorWidthMm, double focusMeters,
                      double fNumber) {
  ThinLens lens;
  lens.focalMm = focalPx * sensorWidthMm / std::max(1, widthPx);
  lens.pxPerMm = double(widthPx) / sensorWidthMm;
  lens.focusMeters = focusMeters;
  const bool usable = focusMeters > 0.0 && fNumber > 0.0 && focusMeters * 1e3 > lens.focalMm;
  lens.fNumber = usable ? fNumber : 0.0;
  return lens;
}

double ThinLens::blurPx(double depthMeters) const {
  if (!defocuses()) return 0.0;
  const double focusMm = focusMeters * 1e3, depthMm = depthMeters * 1e3;
  return focalMm / fNumber * std::abs(depthMm - focusMm) / depthMm * focalMm / (focusMm - focalMm) *
         pxPerMm;
}

double ThinLens::nearestWithBlurMeters(double maxBlurPx) const {
  if (!defocuses()) return focusMeters;
  // In front of the focus c = k (s - d) / d with k = A f / (s - f) in pixels: d = s k / (c + k).
  const double focusMm = focusMeters * 1e3;
  const double k = focalMm / fNumber * focalMm / (focusMm - focalMm) * pxPerMm;
  return focusMeters * k / (std::max(0.0, maxBlurPx) + k);
}

}  // namespace pluvia::rain
