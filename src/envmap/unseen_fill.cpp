// Filling the unseen directions of a stitched panorama (unseen_fill.h).
#include "envmap/unseen_fill.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include <fmt/format.h>

namespace pluvia::envmap {
namespace {

constexpr double kSceneAlbedo = 0.18;
// Seen sky texels given to the fit, at most (a regular subsample): enough for five parameters.
constexpr int kMaxSkySamples = 1500;
// The ratio seen / model at the boundary is trusted within these bounds (a lamp or a dark
// building at the edge of the coverage is not a sky to scale).
constexpr double kMaxBoundaryRatio = 8.0;

Vec3 texelDirection(int width, int height, int x, int y) {
  return equirectTexelDirection(width, height, x, y);
}

// The ground's radiance: the seen ground's solid-angle mean, or albedo 0.18 under the sky.
std::array<double, 3> groundRadiance(const EquirectMap& map, const cv::Mat& coverage,
                                     const std::optional<SkyFit>& sky, double& seenWeight) {
  std::array<double, 3> sum{0, 0, 0};
  seenWeight = 0.0;
  const int w = map.width, h = map.height;
  for (int y = h / 2; y < h; ++y) {
    const double solid = equirectTexelSolidAngle(w, h, y);
    const uchar* c = coverage.ptr<uchar>(y);
    for (int x = 0; x < w; ++x) {
      if (!c[x]) continue;
      const float* v = map.texel(x, y);
      for (size_t k = 0; k < 3; ++k) sum[k] += solid * v[k];
      seenWeight += solid;
    }
  }
  if (seenWeight > 0) {
    for (double& s : sum) s /= seenWeight;
    return sum;
  }
  const auto e = skyIrradiance(*sky);  // a Lambertian ground: L = albedo E / pi
  return {kSceneAlbedo * e[0] / CV_PI, kSceneAlbedo * e[1] / CV_PI, kSceneAlbedo * e[2] / CV_PI};
}

}  // namespace

std::vector<int> nearestSeenTexels(const cv::Mat& coverage) {
  const int w = coverage.cols, h = coverage.rows;
  std::vector<int> nearest(size_t(w) * size_t(h), -1);
  if (cv::countNonZero(coverage) == 0) return nearest;
  // Distance transform on the map tripled horizontally, so the nearest may lie across the
  // u = 0 / 1 seam.
  cv::Mat tripled(h, 3 * w, CV_8UC1);
  for (int y = 0; y < h; ++y) {
    const uchar* c = coverage.ptr<uchar>(y);
    uchar* t = tripled.ptr<uchar>(y);
    for (int x = 0; x < 3 * w; ++x) t[x] = c[x % w] ? 0 : 255;  // zero: seen
  }
  cv::Mat dist, labels;
  cv::distanceTransform(tripled, dist, labels, cv::DIST_L2, cv::DIST_MASK_5, cv::DIST_LABEL_PIXEL);
  // DIST_LABEL_PIXEL numbers the zero pixels 1, 2, ... in raster order.
  std::vector<int> labelIndex(1, -1);
  for (int y = 0; y < h; ++y) {
    const uchar* t = tripled.ptr<uchar>(y);
    for (int x = 0; x < 3 * w; ++x)
      if (!t[x]) labelIndex.push_back(y * w + x % w);
  }
  tbb::parallel_for(0, h, [&](int y) {
    const int* l = labels.ptr<int>(y);
    const uchar* c = coverage.ptr<uchar>(y);
    for (int x = 0; x < w; ++x) {
      const int label = l[x + w];
      if (c[x])
        nearest[size_t(y) * size_t(w) + size_t(x)] = y * w + x;
      else if (label > 0 && label < int(labelIndex.size()))
        nearest[size_t(y) * size_t(w) + size_t(x)] = labelIndex[size_t(label)];
    }
  });
  return nearest;
}

void fillNearest(EquirectMap& map, const cv::Mat& coverage, const std::vector<int>& nearest) {
  const int w = map.width, h = map.height;
  tbb::parallel_for(0, h, [&](int y) {
    const uchar* c = coverage.ptr<uchar>(y);
    for (int x = 0; x < w; ++x) {
      const int n = nearest[size_t(y) * size_t(w) + size_t(x)];
      if (c[x] || n < 0) continue;
      const float* src = map.texel(n % w, n / w);
      float* dst = map.texel(x, y);
      for (int k = 0; k < 3; ++k) dst[k] = src[k];
    }
  });
}

bool fillModel(EquirectMap& map, const cv::Mat& coverage, const cv::Mat& clipped,
               const std::vector<int>& nearest, const ModelFillSettings& settings,
               std::string& model) {
  const int w = map.width, h = map.height;
  // The seen, unclipped sky, subsampled on a regular grid.
  int skyTexels = 0;
  for (int y = 0; y < h / 2; ++y) skyTexels += cv::countNonZero(coverage.row(y));
  const int step = std::max(1, int(std::ceil(std::sqrt(double(skyTexels) / kMaxSkySamples))));
  std::vector<SkySample> samples;
  for (int y = step / 2; y < h / 2; y += step) {
    const double solid = equirectTexelSolidAngle(w, h, y);
    for (int x = step / 2; x < w; x += step) {
      if (!coverage.at<uchar>(y, x) || (!clipped.empty() && clipped.at<uchar>(y, x))) continue;
      const float* v = map.texel(x, y);
      samples.push_back({texelDirection(w, h, x, y), {v[0], v[1], v[2]}, solid});
    }
  }
  SkyFitSettings fitSettings;
  fitSettings.sun = settings.sun;
  std::optional<SkyFit> sky = fitSky(samples, fitSettings);
  double groundWeight = 0.0;
  std::array<double, 3> ground{0, 0, 0};
  if (sky) {
    ground = groundRadiance(map, coverage, sky, groundWeight);
    model = sky->describe();
    if (groundWeight <= 0) model += ", ground it lights";
  } else {
    ground = groundRadiance(map, coverage, SkyFit{}, groundWeight);
    if (groundWeight <= 0) return false;
    // The overcast sky that lights the seen ground at albedo 0.18: E = 7 pi Lz / 9.
    SkyFit overcast;
    overcast.kind = SkyKind::CieOvercast;
    for (size_t k = 0; k < 3; ++k) overcast.scale[k] = ground[k] / kSceneAlbedo * 9.0 / 7.0;
    sky = overcast;
    model = "cie overcast lighting the seen ground";
  }
  auto modelAt = [&](const Vec3& d) {
    return d[1] > 0 ? evaluateSky(*sky, d) : ground;
  };
  const double blend = std::max(settings.blendDeg, 1e-3) * CV_PI / 180.0;
  tbb::parallel_for(0, h, [&](int y) {
    const uchar* c = coverage.ptr<uchar>(y);
    for (int x = 0; x < w; ++x) {
      if (c[x]) continue;
      const Vec3 d = texelDirection(w, h, x, y);
      std::array<double, 3> value = modelAt(d);
      const int n = nearest[size_t(y) * size_t(w) + size_t(x)];
      if (n >= 0) {
        // Towards the seen colour near the boundary, on the same side of the horizon only.
        const int nx = n % w, ny = n / w;
        const Vec3 nd = texelDirection(w, h, nx, ny);
        const double angle =
            std::acos(std::clamp(d[0] * nd[0] + d[1] * nd[1] + d[2] * nd[2], -1.0, 1.0));
        if ((nd[1] > 0) == (d[1] > 0) && angle < blend) {
          const double t = 1.0 - angle / blend;
          const double weight = t * t * (3.0 - 2.0 * t);  // smoothstep: no kink at either end
          const std::array<double, 3> there = modelAt(nd);
          const float* seen = map.texel(nx, ny);
          for (size_t k = 0; k < 3; ++k) {
            const double ratio = std::clamp(double(seen[k]) / std::max(there[k], 1e-30),
                                            1.0 / kMaxBoundaryRatio, kMaxBoundaryRatio);
            value[k] *= std::pow(ratio, weight);
          }
        }
      }
      float* out = map.texel(x, y);
      for (size_t k = 0; k < 3; ++k) out[k] = float(value[k]);
    }
  });
  return true;
}

}  // namespace pluvia::envmap
