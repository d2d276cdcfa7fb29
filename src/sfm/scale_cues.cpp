#include "sfm/scale_cues.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

namespace pluvia::sfm {
namespace {

double percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return NAN;
  auto at = values.begin() + static_cast<long>(fraction * (values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  return *at;
}

void checkHeights(SfmReconstruction& sfm, const SfmOptions& options) {
  std::vector<double> heights;
  for (const SfmKeyframe& key : sfm.keyframes)
    if (std::isfinite(key.heightAboveGroundMeters)) heights.push_back(key.heightAboveGroundMeters);
  if (heights.size() < 2) return;
  const auto [lo, hi] = std::minmax_element(heights.begin(), heights.end());
  double mean = 0.0;
  for (double h : heights) mean += h;
  mean /= static_cast<double>(heights.size());
  double variance = 0.0;
  for (double h : heights) variance += (h - mean) * (h - mean);
  variance /= static_cast<double>(heights.size());
  // The standard deviation, not the range: one photo taken crouching (Sceaux Castle's first, a
  // quarter of a metre under the others) should not by itself call a model bent. Over the mean's
  // magnitude: cameras below the ground (a mean near or under 0) are the most bent of all.
  const double spread = std::sqrt(variance) / std::abs(mean);
  sfm.cameraHeightSpread = spread;
  if (spread > options.maxCameraHeightSpread)
    sfm.warnings.push_back(fmt::format(
        "camera heights above the fitted ground range from {:.2f} to {:.2f} m (standard deviation "
        "{:.0f} % of their mean; at most {:.0f} % expected of a hand-held or vehicle camera): the "
        "ground or the scale is doubtful",
        *lo, *hi, 100.0 * spread, 100.0 * options.maxCameraHeightSpread));

  std::vector<double> pointHeights;
  for (const Eigen::Vector3d& p : sfm.pointsMeters)
    pointHeights.push_back(sfm.groundNormal.dot(p) + sfm.groundOffsetMeters);
  sfm.structureHeightMeters = percentile(pointHeights, 0.95);
  if (sfm.verticalLineCount > 0 &&
      sfm.structureHeightMeters < options.minStructureOverCameraHeight * mean)
    sfm.warnings.push_back(fmt::format(
        "{} façade lines show buildings, but the points' 95th-percentile height above the ground "
        "is {:.2f} m, {:.1f} camera heights (at least {:.1f} expected): the camera height "
        "({:.2f} m) or the ground is doubtful",
        sfm.verticalLineCount, sfm.structureHeightMeters, sfm.structureHeightMeters / mean,
        options.minStructureOverCameraHeight, mean));
}

void checkSpeed(SfmReconstruction& sfm, const SfmOptions& options) {
  if (options.framesPerSecond <= 0.0 || sfm.keyframes.size() < 2) return;
  std::vector<double> speeds;
  for (size_t k = 1; k < sfm.keyframes.size(); ++k) {
    const SfmKeyframe& a = sfm.keyframes[k - 1];
    const SfmKeyframe& b = sfm.keyframes[k];
    const double seconds = static_cast<double>(b.frame - a.frame) / options.framesPerSecond;
    if (seconds > 0.0)
      speeds.push_back((b.camera.positionMeters - a.camera.positionMeters).norm() / seconds);
  }
  sfm.medianCameraSpeedMetersPerSecond = percentile(speeds, 0.5);
  if (sfm.medianCameraSpeedMetersPerSecond > options.maxCameraSpeedMetersPerSecond)
    sfm.warnings.push_back(fmt::format(
        "the camera moves {:.1f} m/s between registered frames at {:.3g} fps (at most {:.0f} m/s "
        "expected): the scale is doubtful",
        sfm.medianCameraSpeedMetersPerSecond, options.framesPerSecond,
        options.maxCameraSpeedMetersPerSecond));
}

}  // namespace

void checkScaleCues(SfmReconstruction& sfm, const SfmOptions& options) {
  if (sfm.groundTiltFromVerticalDeg > options.maxGroundTiltFromVerticalDeg)
    sfm.warnings.push_back(fmt::format(
        "the ground fitted below the cameras tilts {:.1f} deg from the vertical of {} façade lines "
        "(at most {:.0f} expected of a street): a steep slope, or a bent reconstruction; rain "
        "falls along the lines' vertical",
        sfm.groundTiltFromVerticalDeg, sfm.verticalLineCount,
        options.maxGroundTiltFromVerticalDeg));
  if (sfm.groundAtYZero) checkHeights(sfm, options);
  checkSpeed(sfm, options);
}

double bentness(const SfmReconstruction& sfm, const SfmOptions& options, std::string* reason) {
  const double tilt = std::isfinite(sfm.groundTiltFromVerticalDeg)
                          ? sfm.groundTiltFromVerticalDeg / options.maxGroundTiltFromVerticalDeg
                          : 0.0;
  const double spread = std::isfinite(sfm.cameraHeightSpread)
                            ? sfm.cameraHeightSpread / options.maxCameraHeightSpread
                            : 0.0;
  const double worst = std::max(tilt, spread);
  if (reason && worst > 1.0)
    *reason = tilt >= spread
                  ? fmt::format("the ground tilts {:.1f} deg from the façades' vertical",
                                sfm.groundTiltFromVerticalDeg)
                  : fmt::format("the camera heights' standard deviation is {:.0f} % of their mean",
                                100.0 * sfm.cameraHeightSpread);
  return worst;
}

}  // namespace pluvia::sfm
