#include "lab/ground_layer.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "util/median.h"

namespace pluvia::lab {
namespace {

constexpr int kMinAreaPx = 2, kMaxAreaPx = 400;

}  // namespace

GroundStats measureGroundLayers(const std::vector<cv::Mat1f>& layers) {
  GroundStats stats;
  std::vector<double> areas, deltas;
  std::vector<cv::Point2d> previous;
  double blobsPerMpxSum = 0.0;
  size_t continued = 0, counted = 0;  // blobs of frames after the first
  for (size_t f = 0; f < layers.size(); ++f) {
    const cv::Mat1f& layer = layers[f];
    const int top = int(std::lround(kGroundTopFraction * layer.rows));
    const cv::Mat1f ground = layer.rowRange(top, layer.rows);
    const cv::Mat1b above = cv::abs(ground) > kGroundBlobCodes;
    cv::Mat1i labels, boxes;
    cv::Mat1d centroids;
    const int count = cv::connectedComponentsWithStats(above, labels, boxes, centroids, 8, CV_32S);
    std::vector<int> kept(size_t(count), 0);
    std::vector<cv::Point2d> now;
    for (int b = 1; b < count; ++b) {
      const int area = boxes(b, cv::CC_STAT_AREA), w = boxes(b, cv::CC_STAT_WIDTH),
                h = boxes(b, cv::CC_STAT_HEIGHT);
      if (area < kMinAreaPx || area > kMaxAreaPx) continue;
      if (std::max(w, h) > kRoundAspect * std::min(w, h)) continue;
      kept[size_t(b)] = 1;
      areas.push_back(area);
      const cv::Point2d centre(centroids(b, 0), centroids(b, 1));
      now.push_back(centre);
      if (f > 0) {
        ++counted;
        for (const cv::Point2d& p : previous)
          if (std::hypot(p.x - centre.x, p.y - centre.y) <= kContinuePx) {
            ++continued;
            break;
          }
      }
    }
    for (int y = 0; y < ground.rows; ++y)
      for (int x = 0; x < ground.cols; ++x)
        if (kept[size_t(labels(y, x))]) deltas.push_back(std::abs(ground(y, x)));
    blobsPerMpxSum += double(now.size()) * 1e6 / double(ground.total());
    previous = std::move(now);
  }
  stats.frames = int(layers.size());
  if (layers.empty()) return stats;
  stats.blobsPerMpx = blobsPerMpxSum / double(layers.size());
  stats.areaP50Px = quantileInPlace(areas, 0.5);
  stats.deltaP90 = quantileInPlace(deltas, 0.9);
  const double share = counted ? double(continued) / double(counted) : 0.0;
  stats.lifetimeFrames = std::min(1.0 / std::max(1.0 - share, 1e-9), double(layers.size()));
  return stats;
}

}  // namespace pluvia::lab
