#include "stages/plate_lights.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace pluvia {
namespace {

constexpr int kRimInnerPx = 1, kRimOuterPx = 4;

}  // namespace

double medianLuminance(const Image& still) {
  std::vector<float> luminance(static_cast<size_t>(still.width) * still.height);
  for (size_t i = 0; i < luminance.size(); ++i) {
    const float* p = &still.rgba[i * 4];
    luminance[i] = 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
  }
  if (luminance.empty()) return 0.0;
  std::nth_element(luminance.begin(), luminance.begin() + luminance.size() / 2, luminance.end());
  return luminance[luminance.size() / 2];
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
        rimLuminance += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
        if (std::max({p[0], p[1], p[2]}) >= clipLevel) continue;
        for (int c = 0; c < 3; ++c) sum[size_t(c)] += std::max(0.0f, p[c]);
        ++unclipped;
      }
    if (!blob.rimPixels.empty()) blob.rimLuminance = rimLuminance / blob.rimPixels.size();
    const double peak = std::max({sum[0], sum[1], sum[2]});
    if (unclipped > 0 && peak > 0.0)
      for (int c = 0; c < 3; ++c) blob.rgb[size_t(c)] = sum[size_t(c)] / peak;
    blobs.push_back(std::move(blob));
  }
  return blobs;
}

LightSpec plateLight(const PlateBlob& blob, const Camera& camera, const std::vector<float>* depth,
                     double backdropMeters, double clipLevel, double coreGain) {
  std::vector<float> rimDepth;
  if (depth)
    for (int pixel : blob.rimPixels) {
      const float z = (*depth)[size_t(pixel)];
      if (std::isfinite(z) && z > 0.0f) rimDepth.push_back(z);
    }
  double zMeters = backdropMeters;
  if (!rimDepth.empty()) {
    std::nth_element(rimDepth.begin(), rimDepth.begin() + rimDepth.size() / 2, rimDepth.end());
    zMeters = rimDepth[rimDepth.size() / 2];
  }
  // rayCamera has z = -1: scaled by the z-depth it reaches the lamp.
  const Eigen::Vector3d local = camera.rayCamera(blob.xPx, blob.yPx) * zMeters;
  const Eigen::Vector3d world = camera.positionMeters + camera.worldFromCamera * local;
  const double distance = local.norm();
  // A disc of radiance L seen under the solid angle Omega at distance d has the radiant
  // intensity L * Omega * d^2 (its projected area times L); Omega = area / f^2 per pixel. A
  // clipped pixel only says L >= the clip level: coreGain is the guess of how far above it the
  // bulb is (lights.find_core_gain).
  const double solidAngle = blob.areaPx / (camera.focalPx * camera.focalPx);
  LightSpec light;
  light.worldFrame = true;
  light.xMeters = Ramp(world.x());
  light.yMeters = Ramp(world.y());
  light.zMeters = Ramp(world.z());
  light.rgb = blob.rgb;
  light.intensity = Ramp(coreGain * clipLevel * solidAngle * distance * distance);
  light.radiusMeters = std::max(1e-3, std::sqrt(blob.areaPx / M_PI) / camera.focalPx * distance);
  return light;
}

}  // namespace pluvia
