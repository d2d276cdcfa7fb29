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

// A clipped blob larger than this share of the frame is a clipped sky or a lit facade, not a
// lamp. A street lamp on a real night clip (a still camera) is a clipped disc of 1.4 % of the frame
// (5818 px of 854 x 480, its glow fading to 0.025 two radii out), 7.6 % of a 320 x 240 crop
// around it; 0.5 % lost it.
constexpr double kMaxLampShareOfFrame = 0.1;
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
// A lamp's glow is no part of the scene's brightness: the pixels over kNightUpperLuminance joined
// to a clipped core (max channel at kGlowCoreLevel, lights.find_level's default) are a glow, left
// out of the quantiles, when nine tenths of the region lie within kGlowCoreRadii of the core's
// radius (plus kGlowMarginPx) around it and it fades away from it: the farther half of its
// pixels under kGlowFade of the nearer half's mean luminance. The street lamp above fills 15 % of a
// crop with its glow; the weir's sunlit wall, as bright far from its clipped railing as beside it,
// stays in.
constexpr float kGlowCoreLevel = 0.95f;
constexpr double kGlowCoreRadii = 8.0, kGlowMarginPx = 8.0, kGlowFade = 0.75;

// The lamp glows (above) in `luminance` (width x height) of `still`: 255 on their pixels, and
// each glow's core (centroid and radius, px).
struct LampGlow {
  double xPx = 0.0, yPx = 0.0, coreRadiusPx = 0.0;
};
struct LampGlows {
  cv::Mat1b mask;
  std::vector<LampGlow> glows;
};
LampGlows lampGlows(const Image& still, const std::vector<float>& luminance) {
  const int width = still.width, height = still.height;
  cv::Mat1b bright(height, width), core(height, width);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * width + x;
      const float* p = &still.rgba[i * 4];
      bright(y, x) = luminance[i] >= kNightUpperLuminance ? 255 : 0;
      core(y, x) = std::max({p[0], p[1], p[2]}) >= kGlowCoreLevel ? 255 : 0;
    }
  cv::Mat1i labels;
  const int count = cv::connectedComponents(bright, labels, 8, CV_32S);
  // Per bright region: its clipped pixels' count and centroid, then its unclipped pixels'
  // distances from that and luminances.
  struct Region {
    double coreArea = 0, sx = 0, sy = 0;
    std::vector<std::pair<double, float>> around;
  };
  std::vector<Region> regions(count);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (const int l = labels(y, x); l > 0 && core(y, x))
        regions[l].coreArea += 1, regions[l].sx += x, regions[l].sy += y;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      Region& r = regions[labels(y, x)];
      if (labels(y, x) == 0 || !(r.coreArea > 0) || core(y, x)) continue;
      r.around.push_back({std::hypot(x - r.sx / r.coreArea, y - r.sy / r.coreArea),
                          luminance[size_t(y) * width + x]});
    }
  std::vector<uchar> glow(count, 0);
  LampGlows found;
  for (int l = 1; l < count; ++l) {
    Region& r = regions[l];
    if (!(r.coreArea > 0) || r.coreArea > kMaxLampShareOfFrame * width * height) continue;
    const double radius = std::sqrt(r.coreArea / M_PI);
    const LampGlow lamp{r.sx / r.coreArea, r.sy / r.coreArea, radius};
    if (r.around.size() < 2) {
      glow[l] = 1;
      found.glows.push_back(lamp);
      continue;
    }
    // The region's reach: the distance nine tenths of the pixels around the core lie within (a
    // lit pole or leaves joined to the glow stretch the region without making it less of one).
    std::sort(r.around.begin(), r.around.end());
    const double reach = r.around[r.around.size() * 9 / 10].first;
    // The nearer and the farther half of those pixels, by their mean luminance.
    const size_t half = r.around.size() / 2;
    double nearSum = 0, farSum = 0;
    for (size_t i = 0; i < r.around.size(); ++i)
      (i < half ? nearSum : farSum) += r.around[i].second;
    const bool fades = farSum / double(r.around.size() - half) < kGlowFade * nearSum / double(half);
    glow[l] = reach <= kGlowCoreRadii * radius + kGlowMarginPx && fades;
    if (glow[l]) found.glows.push_back(lamp);
  }
  found.mask = cv::Mat1b(height, width);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) found.mask(y, x) = glow[labels(y, x)] ? 255 : 0;
  return found;
}

// How far a lamp's glow reaches: the radius (px, from the core's centre) where the mean
// luminance of a one-pixel ring has lost kGlowFadedShare of its excess over the farthest ring
// (kGlowCoreRadii core radii out, plus kGlowMarginPx, or the farthest the frame holds; the rings'
// pixels inside the frame).
constexpr double kGlowFadedShare = 0.9;
double glowReachPx(const LampGlow& lamp, const std::vector<float>& luminance, int width,
                   int height) {
  const int rings = int(std::ceil(kGlowCoreRadii * lamp.coreRadiusPx + kGlowMarginPx)) + 1;
  std::vector<double> sum(size_t(rings), 0.0), count(size_t(rings), 0.0);
  const int x0 = std::max(0, int(lamp.xPx) - rings), x1 = std::min(width, int(lamp.xPx) + rings);
  const int y0 = std::max(0, int(lamp.yPx) - rings), y1 = std::min(height, int(lamp.yPx) + rings);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const auto ring = size_t(std::hypot(x - lamp.xPx, y - lamp.yPx));
      if (ring >= size_t(rings)) continue;
      sum[ring] += luminance[size_t(y) * size_t(width) + size_t(x)];
      count[ring] += 1.0;
    }
  const auto mean = [&](size_t ring) { return count[ring] > 0 ? sum[ring] / count[ring] : 0.0; };
  const auto edge = size_t(std::ceil(lamp.coreRadiusPx));
  if (edge + 1 >= size_t(rings)) return lamp.coreRadiusPx;
  size_t farthest = size_t(rings) - 1;
  while (farthest > edge && count[farthest] == 0) --farthest;
  const double far = mean(farthest), excess = mean(edge) - far;
  for (size_t ring = edge; ring <= farthest; ++ring)
    if (count[ring] > 0 && mean(ring) - far <= (1.0 - kGlowFadedShare) * excess)
      return double(ring);
  return double(farthest);
}

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

// lampShare at the image's own size.
std::vector<float> lampShareAtSize(const Image& image) {
  std::vector<float> luminance(image.pixelCount());
  for (size_t i = 0; i < luminance.size(); ++i)
    luminance[i] = rec709LuminanceFloat(&image.rgba[i * 4]);
  std::vector<float> share(luminance.size(), 0.0f);
  if (share.empty()) return share;
  const LampGlows found = lampGlows(image, luminance);
  if (found.glows.empty()) return share;
  // The glow mask (the light over kNightUpperLuminance joined to the core), feathered ...
  cv::Mat1f distance;
  cv::distanceTransform(found.mask == 0, distance, cv::DIST_L2, 3);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      share[size_t(y) * size_t(image.width) + size_t(x)] =
          float(std::max(0.0, 1.0 - distance(y, x) / kLampFeatherPx));
  // ... and the disc the glow's light reaches: the fainter glow beyond the mask, feathered over
  // as far again (a graded night sky's airlight beside an ungraded glow showed a ring at 8 px).
  for (const LampGlow& lamp : found.glows) {
    const double reach = glowReachPx(lamp, luminance, image.width, image.height);
    const double feather = std::max(kLampFeatherPx, reach);
    const int extent = int(std::ceil(reach + feather));
    for (int y = std::max(0, int(lamp.yPx) - extent);
         y < std::min(image.height, int(lamp.yPx) + extent + 1); ++y)
      for (int x = std::max(0, int(lamp.xPx) - extent);
           x < std::min(image.width, int(lamp.xPx) + extent + 1); ++x) {
        const double d = std::hypot(x - lamp.xPx, y - lamp.yPx);
        float& s = share[size_t(y) * size_t(image.width) + size_t(x)];
        s = std::max(s, float(std::clamp(1.0 - (d - reach) / feather, 0.0, 1.0)));
      }
  }
  return share;
}

}  // namespace

std::vector<float> lampShare(const Image& image) {
  const int factor = (image.width + kLampShareWidthPx - 1) / kLampShareWidthPx;
  if (factor <= 1) return lampShareAtSize(image);
  // Found at a fraction of the size (the share is smooth), then brought back to it.
  Image small((image.width + factor - 1) / factor, (image.height + factor - 1) / factor);
  cv::resize(const_cast<Image&>(image).rgbaMat(), small.rgbaMat(), small.rgbaMat().size(), 0, 0,
             cv::INTER_AREA);
  const std::vector<float> found = lampShareAtSize(small);
  cv::Mat1f share(image.height, image.width);
  cv::resize(cv::Mat1f(small.height, small.width, const_cast<float*>(found.data())), share,
             share.size(), 0, 0, cv::INTER_LINEAR);
  return {share.begin(), share.end()};
}

PlateLuminance plateLuminance(const Image& still) {
  std::vector<float> all(static_cast<size_t>(still.width) * still.height);
  for (size_t i = 0; i < all.size(); ++i) all[i] = rec709LuminanceFloat(&still.rgba[i * 4]);
  if (all.empty()) return {};
  const cv::Mat1b glow = lampGlows(still, all).mask;
  std::vector<float> luminance;
  luminance.reserve(all.size());
  for (size_t i = 0; i < all.size(); ++i)
    if (!glow(int(i / still.width), int(i % still.width))) luminance.push_back(all[i]);
  if (luminance.empty()) luminance = all;
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
    const bool bulb = blob.rimLuminance < darkRim;
    const bool inGlow = !bulb && blob.surroundLuminance < 0.5 * darkRim;
    const bool source = bulb || inGlow;
    if (blob.areaPx > maxArea || !source) {
      log::debug(fmt::format(
          "lights: clipped blob at ({:.1f}, {:.1f}) px, {} px, not a lamp: {} (rim {:.3f}, "
          "surround {:.3f})",
          blob.xPx, blob.yPx, blob.areaPx,
          blob.areaPx > maxArea ? "larger than a lamp" : "bright around it", blob.rimLuminance,
          blob.surroundLuminance));
      continue;
    }
    // A clipped disc inside its own glow is the glow's saturated centre, not the bulb: taken at
    // the clip level (a lower bound). Over its whole disc, find_core_gain lit every drop in a
    // night clip's frame from a street lamp 20 m off: 142 times the real rain's coverage (the
    // real drops that show are those near the lamp; README, "Night").
    lamps.push_back(plateLamp(blob, camera, depth, backdropMeters, settings.findClipLevel,
                              inGlow ? 1.0 : settings.findCoreGain));
    const FoundLamp& l = lamps.back();
    log::info(fmt::format(
        "lights: found at ({:.1f}, {:.1f}) px, {} px, {:.2f} m deep: world ({:.2f}, {:.2f}, "
        "{:.2f}) m, colour ({:.2f}, {:.2f}, {:.2f}), intensity {:.3g}{}",
        l.xPx, l.yPx, l.areaPx, l.depthMeters, l.worldMeters[0], l.worldMeters[1], l.worldMeters[2],
        l.rgb[0], l.rgb[1], l.rgb[2], l.intensity,
        inGlow ? " (a clipped core in its own glow: taken at the clip level)" : ""));
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
