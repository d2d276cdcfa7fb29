#include "derain/plate_rain.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "derain/clean_plate.h"
#include "derain/dense_flow.h"
#include "derain/streak_stats.h"
#include "util/error.h"

namespace pluvia::derain {
std::string PlateRain::summary() const {
  if (!unmeasured.empty()) return unmeasured;
  std::string angle = std::isfinite(stats.angleDeg)
                          ? fmt::format(", falling at {:.1f} deg", stats.angleDeg)
                          : std::string();
  return fmt::format("streaks over {:.2f} % of the frame, {:.0f} per Mpx{} ({} frames measured)",
                     100.0 * stats.coverage, stats.streaksPerMpx, angle, frames);
}

PlateRain measurePlateRain(const std::vector<cv::Mat3f>& bgrFrames,
                           const PlateRainSettings& settings) {
  const int count = int(bgrFrames.size());
  if (count < 3)
    throw Error(fmt::format("plate rain: {} frames; a clean plate needs 3 or more", count));
  if (!denseFlowMeasures(bgrFrames.front().size())) {
    PlateRain tooSmall;
    tooSmall.unmeasured = fmt::format(
        "not looked for: frames of {}x{} px are too small to follow their motion (needs {} px on "
        "a side)",
        bgrFrames.front().cols, bgrFrames.front().rows, kDenseFlowMinSidePx);
    return tooSmall;
  }
  const int measured = std::clamp(settings.measuredFrames, 1, count);
  const int first = (count - measured) / 2;
  std::vector<int> at;
  for (int k = 0; k < measured; ++k) at.push_back(first + k);
  const std::vector<CleanPlate> plates = cleanPlatesAt(bgrFrames, at);
  StreakStatsAccumulator accumulator;
  for (size_t k = 0; k < at.size(); ++k) {
    RainLayerFrame layer;
    layer.plateLuma = lumaOf(plates[k].plate, ChannelOrder::bgr);
    layer.layer = lumaOf(bgrFrames[size_t(at[k])], ChannelOrder::bgr) - layer.plateLuma;
    layer.valid = plates[k].valid;
    accumulator.add(layer);
  }
  PlateRain out;
  out.stats = accumulator.result();
  out.frames = measured;
  out.rained = out.stats.coverage >= settings.minCoverage &&
               out.stats.streaksPerMpx >= settings.minStreaksPerMpx;
  return out;
}

}  // namespace pluvia::derain
