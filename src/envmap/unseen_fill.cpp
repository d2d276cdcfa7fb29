// Filling the unseen directions of a stitched panorama (unseen_fill.h).
#include "envmap/unseen_fill.h"

#include "envmap/scene_albedo.h"
#include "image/luminance.h"
#include "util/median.h"
#include "util/parallel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include <fmt/format.h>

namespace pluvia::envmap {
namespace {

// Seen sky texels given to the fit, at most (a regular subsample): enough for five parameters.
constexpr int kMaxSkySamples = 1500;
// Neighbouring sky texels differ by less than this in log luminance (about 8 %).
constexpr double kSmoothLog = 0.08;
// The sky's envelope: texels down to this factor below the fitted sky count as sky.
constexpr double kEnvelope = 1.5;
constexpr int kEnvelopeIterations = 3;
constexpr size_t kMinSkySamples = 20;
// More clipped sky than this times the sky fitted: the fit is not trusted.
constexpr double kMaxClippedSky = 1.0;
// The ratio seen / model at the boundary is trusted within these bounds (a lamp or a dark
// building at the edge of the coverage is not a sky to scale).
constexpr double kMaxBoundaryRatio = 8.0;

Vec3 texelDirection(int width, int height, int x, int y) {
  return equirectTexelDirection(width, height, x, y);
}

// The sky samples to fit: seen, unclipped texels above the horizon that are smooth (no
// neighbour differs by more than kSmoothLog in log luminance: edges of buildings, branches and
// leaves are not sky), on a regular subsample.
std::vector<SkySample> smoothSkyTexels(const EquirectMap& map, const cv::Mat& coverage,
                                       const cv::Mat& clipped) {
  const int w = map.width, h = map.height;
  int skyTexels = 0;
  for (int y = 0; y < h / 2; ++y) skyTexels += cv::countNonZero(coverage.row(y));
  const int step = std::max(1, int(std::ceil(std::sqrt(double(skyTexels) / kMaxSkySamples))));
  auto logLuminance = [&](int x, int y) {
    return std::log(std::max(rec709Luminance(map.texel((x + w) % w, y)), 1e-12));
  };
  std::vector<SkySample> samples;
  for (int y = step / 2; y < h / 2; y += step) {
    const double solid = equirectTexelSolidAngle(w, h, y);
    for (int x = step / 2; x < w; x += step) {
      if (!coverage.at<uchar>(y, x) || (!clipped.empty() && clipped.at<uchar>(y, x))) continue;
      const double here = logLuminance(x, y);
      bool smooth = true;
      for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int ny = y + dy, nx = (x + dx + w) % w;
        if (ny < 0 || ny >= h || !coverage.at<uchar>(ny, nx)) continue;
        smooth = smooth && std::abs(logLuminance(nx, ny) - here) < kSmoothLog;
      }
      if (!smooth) continue;
      const float* v = map.texel(x, y);
      samples.push_back({texelDirection(w, h, x, y), {v[0], v[1], v[2]}, solid * step * step});
    }
  }
  return samples;
}

// The sky is the bright envelope of what is seen above the horizon: whatever stands in front
// of it (buildings, trees, a roof) is darker than the sky it hides. The fit starts from the
// brighter half of the smooth texels and is refitted on those within kEnvelope below the
// model, a few times.
std::optional<SkyFit> fitSkyEnvelope(const std::vector<SkySample>& candidates,
                                     const SkyFitSettings& settings, double& used) {
  if (candidates.empty()) return std::nullopt;
  std::vector<double> luminances;
  for (const SkySample& s : candidates) luminances.push_back(rec709Luminance(s.rgb.data()));
  const double middle = median(luminances);
  std::vector<SkySample> subset;
  for (size_t i = 0; i < candidates.size(); ++i)
    if (luminances[i] >= middle) subset.push_back(candidates[i]);
  std::optional<SkyFit> fit;
  for (int iteration = 0; iteration < kEnvelopeIterations; ++iteration) {
    const std::optional<SkyFit> next = fitSky(subset, settings);
    if (!next) break;
    fit = next;
    used = 0.0;
    for (const SkySample& sample : subset) used += sample.weight;
    std::vector<SkySample> kept;
    for (size_t i = 0; i < candidates.size(); ++i) {
      const auto m = evaluateSky(*fit, candidates[i].direction);
      const double modelLuminance = rec709Luminance(m);
      if (luminances[i] >= modelLuminance / kEnvelope) kept.push_back(candidates[i]);
    }
    if (kept.size() < kMinSkySamples) break;
    subset = std::move(kept);
  }
  return fit;
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
  forEachRow(h, [&](int y) {
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
  forEachRow(h, [&](int y) {
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
  if (cv::countNonZero(coverage) == 0) return false;
  SkyFitSettings fitSettings;
  fitSettings.sun = settings.sun;
  double skySolidAngle = 0.0;  // of the texels the sky was fitted to
  std::optional<SkyFit> sky =
      fitSkyEnvelope(smoothSkyTexels(map, coverage, clipped), fitSettings, skySolidAngle);
  // A sky seen mostly clipped (a bright sky through leaves, a window) cannot be fitted: what is
  // left unclipped is not that sky. The nearest colour then keeps at least the clipped value.
  double clippedSky = 0.0;
  for (int y = 0; y < h / 2 && !clipped.empty(); ++y)
    clippedSky +=
        cv::countNonZero(clipped.row(y) & coverage.row(y)) * equirectTexelSolidAngle(w, h, y);
  if (sky && clippedSky > kMaxClippedSky * skySolidAngle) {
    model = fmt::format("nearest (the seen sky is clipped: {:.3f} sr against {:.3f} sr fitted)",
                        clippedSky, skySolidAngle);
    return false;
  }
  // The ground at the coverage's lower edge (the mean over the unseen ground of the nearest seen
  // colour): a Lambertian ground under the fitted sky has radiance albedo E / pi wherever the
  // sky lights it alike, so the unseen ground takes the seen ground's radiance.
  std::array<double, 3> ground{0, 0, 0};
  double groundWeight = 0.0;
  for (int y = h / 2; y < h; ++y) {
    const double solid = equirectTexelSolidAngle(w, h, y);
    for (int x = 0; x < w; ++x) {
      const int n = nearest[size_t(y) * size_t(w) + size_t(x)];
      if (coverage.at<uchar>(y, x) || n < 0 || n / w < h / 2) continue;
      const float* v = map.texel(n % w, n / w);
      for (size_t k = 0; k < 3; ++k) ground[k] += solid * v[k];
      groundWeight += solid;
    }
  }
  if (groundWeight > 0)
    for (double& g : ground) g /= groundWeight;
  if (sky) {
    model = sky->describe();
    const auto e = skyIrradiance(*sky);
    if (groundWeight > 0) {
      model += fmt::format(", ground albedo {:.2f}",
                           CV_PI * rec709Luminance(ground) / rec709Luminance(e));
    } else {
      for (size_t k = 0; k < 3; ++k) ground[k] = kMeteredSceneAlbedo * e[k] / CV_PI;
      model += fmt::format(", ground it lights at albedo {}", kMeteredSceneAlbedo);
    }
  } else {
    if (groundWeight <= 0) return false;
    // The overcast sky that lights the seen ground at the metered albedo: E = 7 pi Lz / 9.
    SkyFit overcast;
    overcast.kind = SkyKind::CieOvercast;
    for (size_t k = 0; k < 3; ++k) overcast.scale[k] = ground[k] / kMeteredSceneAlbedo * 9.0 / 7.0;
    sky = overcast;
    model = "cie overcast lighting the seen ground";
  }
  auto modelAt = [&](const Vec3& d) { return d[1] > 0 ? evaluateSky(*sky, d) : ground; };
  const double skyBlend = std::max(settings.skyBlendDeg, 1e-3) * CV_PI / 180.0;
  const double obstacleBlend = std::max(settings.obstacleBlendDeg, 1e-3) * CV_PI / 180.0;
  forEachRow(h, [&](int y) {
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
        const std::array<double, 3> there = modelAt(nd);
        const float* seen = map.texel(nx, ny);
        const double thereLuminance = rec709Luminance(there);
        // Sky at the boundary fades into the model quickly; the ground, and whatever stands in
        // front of the sky there (darker than the sky's envelope), slowly.
        const bool skyThere = d[1] > 0 && rec709Luminance(seen) >= thereLuminance / kEnvelope;
        const double blend = skyThere ? skyBlend : obstacleBlend;
        if ((nd[1] > 0) == (d[1] > 0) && angle < blend) {
          const double t = 1.0 - angle / blend;
          const double weight = t * t * (3.0 - 2.0 * t);  // smoothstep: no kink at either end
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
