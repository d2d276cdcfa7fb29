#include "stages/plate_lights.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "image/luminance.h"
#include "util/log.h"
#include "util/median.h"

namespace pluvia {
namespace {

constexpr int kRimInnerPx = 1, kRimOuterPx = 4;
// The surround ring, in blob radii, and its least extent.
constexpr double kSurroundInnerRadii = 2.0, kSurroundOuterRadii = 4.0;
constexpr int kSurroundInnerPx = 8, kSurroundOuterPx = 16;

// A clipped blob larger than this share of the frame is a clipped sky or window, not a lamp.
constexpr double kMaxLampShareOfFrame = 0.005;
// lights.find auto looks for lamps on night plates only: a day plate's clipped blobs are sky,
// clouds, white walls and glints, not sources. Night: the still's median luminance below
// kNightMedianLuminance (scene-linear; about 31 % grey in sRGB) and its 90th percentile below
// kNightUpperLuminance (about 58 % grey): a day plate mostly in shade (the weir photo of
// ../shared/data: median 0.058) still has a sunlit tenth (its 90th percentile 0.67); a night
// street's lamp-lit pools cover far less than a tenth. And a lamp is a source in the dark: its
// rim's mean luminance below kLampRimOverClip of the clip level (a clipped patch of a lit wall
// has a bright rim).
constexpr double kNightMedianLuminance = 0.08;
constexpr double kNightUpperLuminance = 0.3;
constexpr double kLampRimOverClip = 0.4;

// The mean luminance of the ring kSurroundInner..OuterRadii blob radii around blob `label`.
double surroundLuminanceOf(const Image& still, const cv::Mat& labels, int label,
                           const cv::Mat& stats) {
  const double radius = std::sqrt(stats.at<int>(label, cv::CC_STAT_AREA) / M_PI);
  const int inner = std::max(kSurroundInnerPx, int(std::lround(kSurroundInnerRadii * radius)));
  const int outer = std::max(kSurroundOuterPx, int(std::lround(kSurroundOuterRadii * radius)));
  const cv::Rect box = cv::Rect(stats.at<int>(label, cv::CC_STAT_LEFT) - outer,
                                stats.at<int>(label, cv::CC_STAT_TOP) - outer,
                                stats.at<int>(label, cv::CC_STAT_WIDTH) + 2 * outer,
                                stats.at<int>(label, cv::CC_STAT_HEIGHT) + 2 * outer) &
                       cv::Rect(0, 0, still.width, still.height);
  cv::Mat outside = labels(box) != label, distance;
  cv::distanceTransform(outside, distance, cv::DIST_L2, 3);
  double sum = 0.0;
  int count = 0;
  for (int by = 0; by < box.height; ++by)
    for (int bx = 0; bx < box.width; ++bx) {
      const float d = distance.at<float>(by, bx);
      if (d < inner || d > outer) continue;
      sum += rec709Luminance(&still.rgba[(size_t(box.y + by) * still.width + box.x + bx) * 4]);
      ++count;
    }
  return count > 0 ? sum / count : 0.0;
}

}  // namespace

PlateLuminance plateLuminance(const Image& still) {
  std::vector<float> luminance(static_cast<size_t>(still.width) * still.height);
  for (size_t i = 0; i < luminance.size(); ++i) {
    const float* p = &still.rgba[i * 4];
    luminance[i] = rec709LuminanceFloat(p);
  }
  if (luminance.empty()) return {};
  auto quantile = [&](double fraction) {
    const auto at = luminance.begin() +
                    static_cast<ptrdiff_t>(fraction * static_cast<double>(luminance.size() - 1));
    std::nth_element(luminance.begin(), at, luminance.end());
    return static_cast<double>(*at);
  };
  PlateLuminance result;
  result.median = quantile(0.5);
  result.upperTenth = quantile(0.9);
  return result;
}

bool isNightPlate(const PlateLuminance& luminance) {
  return luminance.median < kNightMedianLuminance && luminance.upperTenth < kNightUpperLuminance;
}

std::vector<PlateBlob> findClippedBlobs(const Image& still, double clipLevel, int minAreaPx) {
  const int width = still.width, height = still.height;
  cv::Mat clipped(height, width, CV_8U);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float* p = &still.rgba[(size_t(y) * width + x) * 4];
      clipped.at<uchar>(y, x) = std::max({p[0], p[1], p[2]}) >= clipLevel ? 255 : 0;
    }
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(clipped, labels, stats, centroids, 8, CV_32S);
  std::vector<PlateBlob> blobs;
  for (int label = 1; label < count; ++label) {
    const int area = stats.at<int>(label, cv::CC_STAT_AREA);
    if (area < minAreaPx) continue;
    PlateBlob blob;
    blob.areaPx = area;
    // OpenCV's centroid is in pixel indices; pixel centres are at +0.5.
    blob.xPx = centroids.at<double>(label, 0) + 0.5;
    blob.yPx = centroids.at<double>(label, 1) + 0.5;
    // The rim is looked for in the blob's box grown by the rim's width, not the whole frame.
    const cv::Rect box = cv::Rect(stats.at<int>(label, cv::CC_STAT_LEFT) - kRimOuterPx,
                                  stats.at<int>(label, cv::CC_STAT_TOP) - kRimOuterPx,
                                  stats.at<int>(label, cv::CC_STAT_WIDTH) + 2 * kRimOuterPx,
                                  stats.at<int>(label, cv::CC_STAT_HEIGHT) + 2 * kRimOuterPx) &
                         cv::Rect(0, 0, width, height);
    const cv::Mat mask = labels(box) == label;
    cv::Mat inner, outer;
    const auto disc = [](int r) {
      return cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1));
    };
    cv::dilate(mask, inner, disc(kRimInnerPx));
    cv::dilate(mask, outer, disc(kRimOuterPx));
    std::array<double, 3> sum{0, 0, 0};
    double rimLuminance = 0.0;
    int unclipped = 0;
    for (int by = 0; by < box.height; ++by)
      for (int bx = 0; bx < box.width; ++bx) {
        if (!outer.at<uchar>(by, bx) || inner.at<uchar>(by, bx)) continue;
        const int x = box.x + bx, y = box.y + by;
        blob.rimPixels.push_back(y * width + x);
        const float* p = &still.rgba[(size_t(y) * width + x) * 4];
        rimLuminance += rec709Luminance(p);
        if (std::max({p[0], p[1], p[2]}) >= clipLevel) continue;
        for (int c = 0; c < 3; ++c) sum[size_t(c)] += std::max(0.0f, p[c]);
        ++unclipped;
      }
    if (!blob.rimPixels.empty()) blob.rimLuminance = rimLuminance / blob.rimPixels.size();
    blob.surroundLuminance = surroundLuminanceOf(still, labels, label, stats);
    const double peak = std::max({sum[0], sum[1], sum[2]});
    if (unclipped > 0 && peak > 0.0)
      for (int c = 0; c < 3; ++c) blob.rgb[size_t(c)] = sum[size_t(c)] / peak;
    blobs.push_back(std::move(blob));
  }
  return blobs;
}

FoundLamp plateLamp(const PlateBlob& blob, const Camera& camera, const std::vector<float>* depth,
                    double backdropMeters, double clipLevel, double coreGain) {
  std::vector<float> rimDepth;
  if (depth)
    for (int pixel : blob.rimPixels) {
      const float z = (*depth)[size_t(pixel)];
      if (std::isfinite(z) && z > 0.0f) rimDepth.push_back(z);
    }
  double zMeters = backdropMeters;
  if (!rimDepth.empty()) zMeters = median(rimDepth);
  // rayCamera has z = -1: scaled by the z-depth it reaches the lamp.
  const Eigen::Vector3d local = camera.rayCamera(blob.xPx, blob.yPx) * zMeters;
  const Eigen::Vector3d world = camera.positionMeters + camera.worldFromCamera * local;
  const double distance = local.norm();
  // A disc of radiance L seen under the solid angle Omega at distance d has the radiant
  // intensity L * Omega * d^2 (its projected area times L); Omega = area / f^2 per pixel. A
  // clipped pixel only says L >= the clip level: coreGain is the guess of how far above it the
  // bulb is (lights.find_core_gain).
  const double solidAngle = blob.areaPx / (camera.focalPx * camera.focalPx);
  FoundLamp lamp;
  lamp.xPx = blob.xPx;
  lamp.yPx = blob.yPx;
  lamp.areaPx = blob.areaPx;
  lamp.depthMeters = zMeters;
  lamp.rgb = blob.rgb;
  lamp.intensity = coreGain * clipLevel * solidAngle * distance * distance;
  lamp.worldMeters = {world.x(), world.y(), world.z()};
  lamp.radiusMeters = std::max(1e-3, std::sqrt(blob.areaPx / M_PI) / camera.focalPx * distance);
  return lamp;
}

LightSpec foundLampLight(const FoundLamp& lamp) {
  LightSpec light;
  light.worldFrame = true;
  light.xMeters = Ramp(lamp.worldMeters[0]);
  light.yMeters = Ramp(lamp.worldMeters[1]);
  light.zMeters = Ramp(lamp.worldMeters[2]);
  light.rgb = lamp.rgb;
  light.intensity = Ramp(lamp.intensity);
  light.radiusMeters = lamp.radiusMeters;
  light.photographed = true;
  return light;
}

std::vector<FoundLamp> findPlateLamps(const Image& still, const LightsSettings& settings,
                                      const Camera& camera, const std::vector<float>* depth,
                                      double backdropMeters) {
  const PlateLuminance luminance = plateLuminance(still);
  if (!settings.findOnDayPlates && !isNightPlate(luminance)) {
    log::info(fmt::format(
        "lights: no lamps looked for: the plate is not a night plate (luminance median {:.3f}, "
        "90th percentile {:.3f}; night: under {:g} and {:g}; lights.find = on looks anyway)",
        luminance.median, luminance.upperTenth, kNightMedianLuminance, kNightUpperLuminance));
    return {};
  }
  const double maxArea = kMaxLampShareOfFrame * still.width * still.height;
  std::vector<FoundLamp> lamps;
  for (const PlateBlob& blob :
       findClippedBlobs(still, settings.findClipLevel, settings.findMinAreaPx)) {
    const double darkRim = kLampRimOverClip * settings.findClipLevel;
    const bool source =
        blob.rimLuminance < darkRim || blob.surroundLuminance < 0.5 * darkRim;  // in its glow
    if (blob.areaPx > maxArea || !source) continue;
    lamps.push_back(plateLamp(blob, camera, depth, backdropMeters, settings.findClipLevel,
                              settings.findCoreGain));
    const FoundLamp& l = lamps.back();
    log::info(fmt::format(
        "lights: found at ({:.1f}, {:.1f}) px, {} px, {:.2f} m deep: world ({:.2f}, {:.2f}, "
        "{:.2f}) m, colour ({:.2f}, {:.2f}, {:.2f}), intensity {:.3g}",
        l.xPx, l.yPx, l.areaPx, l.depthMeters, l.worldMeters[0], l.worldMeters[1], l.worldMeters[2],
        l.rgb[0], l.rgb[1], l.rgb[2], l.intensity));
  }
  log::info(fmt::format(
      "lights: {} lights found in the plate (clipped blobs in the dark, max channel >= "
      "lights.find_level = {:g}){}",
      lamps.size(), settings.findClipLevel,
      lamps.empty() && settings.lights.empty() ? ": nothing to light, the light work is skipped"
                                               : ""));
  return lamps;
}

}  // namespace pluvia
