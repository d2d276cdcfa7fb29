#include "sfm/sparse_densify.h"
#include "util/median.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/edge_filter.hpp>

namespace pluvia::sfm {
namespace {

// 8-bit grey levels for the smoother and the sky test. Float input is taken as linear light and
// given a display gamma, so edges in shadows count as much as they look.
cv::Mat greyGuide(const cv::Mat& guide) {
  cv::Mat grey;
  if (guide.channels() == 1) {
    grey = guide;
  } else {
    cv::cvtColor(guide, grey, guide.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  }
  if (grey.depth() == CV_8U) return grey.clone();
  cv::Mat f;
  grey.convertTo(f, CV_32F);
  cv::max(f, 0.0, f);
  cv::pow(f, 1.0 / 2.2, f);
  cv::Mat out;
  f.convertTo(out, CV_8U, 255.0);
  return out;
}

// Push-pull: sums of weight * value and of weight, reduced 2x2 per level; then, coarse to fine,
// pixels with weight below 1 take the remainder from the upsampled coarser estimate.
cv::Mat pushPull(const cv::Mat& weightedSum, const cv::Mat& weight) {
  std::vector<cv::Mat> sums{weightedSum}, weights{weight};
  while (sums.back().cols > 1 || sums.back().rows > 1) {
    const cv::Mat& s = sums.back();
    const cv::Mat& w = weights.back();
    cv::Mat s2 = cv::Mat::zeros((s.rows + 1) / 2, (s.cols + 1) / 2, CV_32F), w2 = s2.clone();
    for (int y = 0; y < s.rows; ++y)
      for (int x = 0; x < s.cols; ++x) {
        s2.at<float>(y / 2, x / 2) += s.at<float>(y, x);
        w2.at<float>(y / 2, x / 2) += w.at<float>(y, x);
      }
    sums.push_back(s2);
    weights.push_back(w2);
  }
  const float& top = weights.back().at<float>(0, 0);
  cv::Mat value(1, 1, CV_32F, cv::Scalar(top > 0 ? sums.back().at<float>(0, 0) / top : 0.0f));
  for (int level = static_cast<int>(sums.size()) - 2; level >= 0; --level) {
    const cv::Mat& s = sums[level];
    const cv::Mat& w = weights[level];
    cv::Mat up;
    cv::resize(value, up, s.size(), 0, 0, cv::INTER_LINEAR);
    value.create(s.size(), CV_32F);
    for (int y = 0; y < s.rows; ++y)
      for (int x = 0; x < s.cols; ++x) {
        float wi = w.at<float>(y, x);
        float rest = std::max(0.0f, 1.0f - wi);
        value.at<float>(y, x) = (s.at<float>(y, x) + rest * up.at<float>(y, x)) / (wi + rest);
      }
  }
  return value;
}

// Piecewise-linear interpolation over the Delaunay triangulation of the samples (exact for a
// plane, since inverse depth is affine in the image over a plane), written into `out` (CV_32F)
// where `covered` (CV_32F, 1 inside the samples' convex hull, else 0) is set.
void delaunayFill(const std::vector<cv::Point2f>& sites, const std::vector<float>& values,
                  cv::Mat& out, cv::Mat& covered) {
  if (sites.size() < 3) return;
  cv::Subdiv2D subdiv(cv::Rect(-1, -1, out.cols + 2, out.rows + 2));
  std::map<std::pair<int, int>, float> valueAt;  // Subdiv2D returns coordinates, not indices
  for (size_t i = 0; i < sites.size(); ++i) {
    subdiv.insert(sites[i]);
    valueAt[{cvRound(sites[i].x * 64), cvRound(sites[i].y * 64)}] = values[i];
  }
  std::vector<cv::Vec6f> triangles;
  subdiv.getTriangleList(triangles);
  for (const auto& t : triangles) {
    cv::Point2f p[3] = {{t[0], t[1]}, {t[2], t[3]}, {t[4], t[5]}};
    float v[3];
    bool real = true;
    for (int k = 0; k < 3; ++k) {
      auto it = valueAt.find({cvRound(p[k].x * 64), cvRound(p[k].y * 64)});
      if (it == valueAt.end())
        real = false;  // a vertex of Subdiv2D's outer bounding triangle
      else
        v[k] = it->second;
    }
    if (!real) continue;
    double det = (p[1].y - p[2].y) * (p[0].x - p[2].x) + (p[2].x - p[1].x) * (p[0].y - p[2].y);
    if (std::abs(det) < 1e-9) continue;
    int x0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].x, p[1].x, p[2].x}))));
    int x1 =
        std::min(out.cols - 1, static_cast<int>(std::ceil(std::max({p[0].x, p[1].x, p[2].x}))));
    int y0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].y, p[1].y, p[2].y}))));
    int y1 =
        std::min(out.rows - 1, static_cast<int>(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        double px = x + 0.5, py = y + 0.5;
        double a = ((p[1].y - p[2].y) * (px - p[2].x) + (p[2].x - p[1].x) * (py - p[2].y)) / det;
        double b = ((p[2].y - p[0].y) * (px - p[2].x) + (p[0].x - p[2].x) * (py - p[2].y)) / det;
        double c = 1.0 - a - b;
        const double eps = -1e-7;
        if (a < eps || b < eps || c < eps) continue;
        out.at<float>(y, x) = static_cast<float>(a * v[0] + b * v[1] + c * v[2]);
        covered.at<float>(y, x) = 1.0f;
      }
  }
}

// The `k` nearest other points of each point (fewer when there are fewer), nearest first, and
// their distances, through a uniform grid of about one point per cell.
void nearestNeighbours(const std::vector<cv::Point2f>& points, int k,
                       std::vector<std::vector<int>>& neighbours,
                       std::vector<std::vector<float>>& distances) {
  const int n = static_cast<int>(points.size());
  neighbours.assign(n, {});
  distances.assign(n, {});
  if (n < 2 || k <= 0) return;
  float x0 = points[0].x, x1 = x0, y0 = points[0].y, y1 = y0;
  for (const auto& p : points) {
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  }
  const double cell = std::max(1.0, std::sqrt((x1 - x0 + 1.0) * (y1 - y0 + 1.0) / n));
  const int nx = static_cast<int>((x1 - x0) / cell) + 1,
            ny = static_cast<int>((y1 - y0) / cell) + 1;
  auto cellOf = [&](const cv::Point2f& p, int& cx, int& cy) {
    cx = std::min(nx - 1, static_cast<int>((p.x - x0) / cell));
    cy = std::min(ny - 1, static_cast<int>((p.y - y0) / cell));
  };
  std::vector<int> start(static_cast<size_t>(nx) * ny + 1, 0), order(n);
  for (const auto& p : points) {
    int cx, cy;
    cellOf(p, cx, cy);
    ++start[cy * nx + cx + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int i = 0; i < n; ++i) {
    int cx, cy;
    cellOf(points[i], cx, cy);
    order[fill[cy * nx + cx]++] = i;
  }
  std::vector<std::pair<float, int>> found;
  for (int i = 0; i < n; ++i) {
    int cx, cy;
    cellOf(points[i], cx, cy);
    found.clear();
    for (int ring = 0;; ++ring) {
      for (int gy = cy - ring; gy <= cy + ring; ++gy) {
        if (gy < 0 || gy >= ny) continue;
        const bool edgeRow = gy == cy - ring || gy == cy + ring;
        for (int gx = cx - ring; gx <= cx + ring; gx += edgeRow ? 1 : 2 * std::max(ring, 1)) {
          if (gx < 0 || gx >= nx) continue;
          const int c = gy * nx + gx;
          for (int j = start[c]; j < start[c + 1]; ++j) {
            const int other = order[j];
            if (other == i) continue;
            const float dx = points[other].x - points[i].x, dy = points[other].y - points[i].y;
            found.emplace_back(dx * dx + dy * dy, other);
          }
        }
      }
      const bool covered = ring >= std::max({cx, nx - 1 - cx, cy, ny - 1 - cy});
      if (static_cast<int>(found.size()) >= k || covered) {
        const int m = std::min<int>(k, static_cast<int>(found.size()));
        std::partial_sort(found.begin(), found.begin() + m, found.end());
        // Points in cells beyond this ring are at least ring * cell away.
        if (covered || found[m - 1].first <= (ring * cell) * (ring * cell)) {
          for (int j = 0; j < m; ++j) {
            neighbours[i].push_back(found[j].second);
            distances[i].push_back(std::sqrt(found[j].first));
          }
          break;
        }
      }
    }
  }
}

// Whether inverse depth `own` at sample i agrees with the affine function of the image position
// (a plane) fitted to its neighbours, robustly (a second fit without the neighbours far off the
// first). The median of the neighbours is biased where the sample lies at the edge of a steep
// ramp (the ground just below the horizon, sampled from one side); the plane is not.
bool agreesWithLocalPlane(const std::vector<SparseDepthSample>& samples, size_t i,
                          const std::vector<int>& near, double own, double maxRelativeDeviation) {
  std::vector<double> dx, dy, v, residual;
  for (int j : near) {
    if (!(samples[j].depthMeters > 0)) continue;
    dx.push_back(samples[j].xPx - samples[i].xPx);
    dy.push_back(samples[j].yPx - samples[i].yPx);
    v.push_back(1.0 / samples[j].depthMeters);
  }
  const size_t n = v.size();
  if (n < 5) return false;
  std::vector<char> use(n, 1);
  Eigen::Vector3d plane = Eigen::Vector3d::Zero();  // value at the sample, slope in x, in y
  double spread = 0;
  for (int pass = 0; pass < 2; ++pass) {
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    int used = 0;
    for (size_t k = 0; k < n; ++k) {
      if (!use[k]) continue;
      const Eigen::Vector3d row(1.0, dx[k], dy[k]);
      a += row * row.transpose();
      b += row * v[k];
      ++used;
    }
    if (used < 4) return false;
    // Neighbours (nearly) on a line leave the slope across it undetermined.
    const double scale = a(1, 1) + a(2, 2);
    if (!(a.determinant() > 1e-6 * used * scale * scale / 4)) return false;
    plane = a.ldlt().solve(b);
    residual.clear();
    for (size_t k = 0; k < n; ++k)
      if (use[k])
        residual.push_back(std::abs(v[k] - plane[0] - plane[1] * dx[k] - plane[2] * dy[k]));
    spread = 1.4826 * median(residual);
    if (pass == 0)
      for (size_t k = 0; k < n; ++k)
        use[k] = std::abs(v[k] - plane[0] - plane[1] * dx[k] - plane[2] * dy[k]) <=
                 std::max(3.0 * spread, 0.05 * std::abs(v[k]));
  }
  if (!(plane[0] > 0)) return false;
  return std::abs(own - plane[0]) <= std::max(maxRelativeDeviation * plane[0], 3.0 * spread);
}

}  // namespace

std::vector<SparseDepthSample> rejectDepthOutliers(const std::vector<SparseDepthSample>& samples,
                                                   int neighbours, double maxRelativeDeviation) {
  if (neighbours <= 0 || static_cast<int>(samples.size()) < neighbours + 1) return samples;
  std::vector<cv::Point2f> points;
  for (const auto& s : samples)
    points.emplace_back(static_cast<float>(s.xPx), static_cast<float>(s.yPx));
  std::vector<std::vector<int>> near;
  std::vector<std::vector<float>> distances;
  nearestNeighbours(points, neighbours, near, distances);
  std::vector<SparseDepthSample> kept;
  std::vector<float> values;
  for (size_t i = 0; i < samples.size(); ++i) {
    values.clear();
    for (int j : near[i])
      if (samples[j].depthMeters > 0)
        values.push_back(static_cast<float>(1.0 / samples[j].depthMeters));
    if (values.size() < 3 || !(samples[i].depthMeters > 0)) {
      kept.push_back(samples[i]);
      continue;
    }
    const float m = median(values);
    const double own = 1.0 / samples[i].depthMeters;
    // A sample on a depth step (a box's corner among far points) disagrees with the median but
    // has neighbours on its own side of the step: two of them that agree with it keep it.
    int agreeing = 0;
    for (float v : values) agreeing += std::abs(v - own) <= maxRelativeDeviation * own;
    if (std::abs(own - m) <= maxRelativeDeviation * m || agreeing >= 2 ||
        agreesWithLocalPlane(samples, i, near[i], own, maxRelativeDeviation))
      kept.push_back(samples[i]);
  }
  return kept;
}

std::vector<SparseDepthSample> projectSparsePoints(const Camera& camera,
                                                   const std::vector<Eigen::Vector3d>& pointsMeters,
                                                   const std::vector<int>* subset) {
  std::vector<SparseDepthSample> samples;
  auto add = [&](const Eigen::Vector3d& p) {
    SparseDepthSample s;
    if (!camera.project(p, s.xPx, s.yPx, s.depthMeters)) return;
    if (s.xPx < 0 || s.yPx < 0 || s.xPx >= camera.width || s.yPx >= camera.height) return;
    samples.push_back(s);
  };
  if (subset) {
    for (int i : *subset)
      if (i >= 0 && i < static_cast<int>(pointsMeters.size())) add(pointsMeters[i]);
  } else {
    for (const auto& p : pointsMeters) add(p);
  }
  return samples;
}

std::vector<float> densifySparseDepth(const std::vector<SparseDepthSample>& allSamples,
                                      const cv::Mat& guide, const DensifyOptions& options) {
  const int width = guide.cols, height = guide.rows;
  std::vector<float> depth(static_cast<size_t>(width) * height,
                           std::numeric_limits<float>::infinity());
  std::vector<SparseDepthSample> valid;
  for (const auto& s : allSamples) {
    int x = static_cast<int>(std::floor(s.xPx)), y = static_cast<int>(std::floor(s.yPx));
    if (x < 0 || y < 0 || x >= width || y >= height || !(s.depthMeters > 0) ||
        !std::isfinite(s.depthMeters))
      continue;
    valid.push_back(s);
  }
  const std::vector<SparseDepthSample> samples =
      rejectDepthOutliers(valid, options.outlierNeighbours, options.outlierMaxRelativeDeviation);
  if (samples.empty()) return depth;
  cv::Mat sum = cv::Mat::zeros(height, width, CV_32F), weight = sum.clone();
  std::vector<cv::Point2f> sites;
  std::vector<float> siteValues;
  for (const auto& s : samples) {
    int x = static_cast<int>(std::floor(s.xPx)), y = static_cast<int>(std::floor(s.yPx));
    sum.at<float>(y, x) += static_cast<float>(1.0 / s.depthMeters);
    weight.at<float>(y, x) += 1.0f;
    sites.emplace_back(static_cast<float>(s.xPx), static_cast<float>(s.yPx));
    siteValues.push_back(static_cast<float>(1.0 / s.depthMeters));
  }
  // Several samples on one pixel count as one, so dense clusters do not outweigh the prior.
  cv::Mat sampleMask = weight > 0;
  cv::Mat average;
  cv::divide(sum, cv::max(weight, 1.0f), average);
  cv::Mat unitWeight;
  sampleMask.convertTo(unitWeight, CV_32F, 1.0 / 255.0);
  cv::Mat distancePx;
  cv::distanceTransform(sampleMask == 0, distancePx, cv::DIST_L2, 3);

  // The triangulated field, extended past the hull by push-pull from the hull's own values (not
  // from the samples alone, which would leave a seam along the hull's outline).
  cv::Mat triangulated = cv::Mat::zeros(height, width, CV_32F), covered = triangulated.clone();
  delaunayFill(sites, siteValues, triangulated, covered);
  // Samples on the hull whose pixel centre falls just outside it keep their own value.
  average.copyTo(triangulated, sampleMask & (covered == 0));
  const cv::Mat known = cv::max(covered, unitWeight);
  cv::Mat fill = pushPull(triangulated, known);

  cv::Mat groundInverse, sinElevation;
  if (options.groundCamera) {
    groundPlane(*options.groundCamera, width, height, options.groundMaxDistanceMeters,
                groundInverse, sinElevation);
    // The samples correct the ground camera (a height or tilt slightly off): the ratio of the
    // triangulated field to the ground's inverse depth, where the two nearly agree (samples on
    // the ground; walls and boxes are far off), extended everywhere by push-pull.
    cv::Mat ratioSum = cv::Mat::zeros(height, width, CV_32F), ratioWeight = ratioSum.clone();
    for (int y = 0; y < height; ++y) {
      const float* t = triangulated.ptr<float>(y);
      const float* k = known.ptr<float>(y);
      const float* g = groundInverse.ptr<float>(y);
      for (int x = 0; x < width; ++x) {
        if (!(k[x] > 0) || !(g[x] > 0)) continue;
        const float q = t[x] / g[x];
        if (std::abs(q - 1.0f) > options.groundMaxCorrection) continue;
        ratioSum.at<float>(y, x) = q;
        ratioWeight.at<float>(y, x) = 1.0f;
      }
    }
    const cv::Mat ratio = cv::countNonZero(ratioWeight) > 0
                              ? pushPull(ratioSum, ratioWeight)
                              : cv::Mat(height, width, CV_32F, cv::Scalar(1.0f));
    // The (corrected) ground bounds the depth where the samples do not: outside their hull, and
    // inside it with a weight falling from 1 to 0 with the distance to the nearest sample, on
    // the scale of their spacing. At the hull's outline the two agree (both are the samples'
    // values where they lie on the ground), so the bound leaves no seam there.
    std::vector<std::vector<int>> near;
    std::vector<std::vector<float>> distances;
    nearestNeighbours(sites, 1, near, distances);
    std::vector<float> spacing;
    for (const auto& d : distances)
      if (!d.empty() && d[0] > 0.5f) spacing.push_back(d[0]);
    const double scale =
        options.groundBlendSpacings *
        std::max(4.0, spacing.empty() ? 0.02 * std::hypot(width, height) : median(spacing));
    for (int y = 0; y < height; ++y) {
      float* f = fill.ptr<float>(y);
      const float* g = groundInverse.ptr<float>(y);
      const float* q = ratio.ptr<float>(y);
      const float* k = known.ptr<float>(y);
      const float* d = distancePx.ptr<float>(y);
      for (int x = 0; x < width; ++x) {
        const float bound = g[x] * q[x];
        if (bound <= f[x]) continue;
        const double r = d[x] / scale;
        const double sampled = k[x] > 0 ? std::exp(-r * r) : 0.0;
        f[x] += static_cast<float>((1.0 - sampled) * (bound - f[x]));
      }
    }
  }

  cv::Mat grey = greyGuide(guide);
  const float prior = static_cast<float>(options.priorWeight);
  // The smoother averages; an average of a ramp is biased wherever the kernel is cut by an edge
  // (texture, the horizon). So only the samples' departure from the linear fill is smoothed: zero
  // on planes, and spread within edge-bounded regions where the fill smears a depth step.
  cv::Mat numerator = (average - fill).mul(unitWeight);
  cv::Mat denominator = unitWeight + prior;
  cv::Mat both, smoothed;
  cv::merge(std::vector<cv::Mat>{numerator, denominator}, both);
  cv::ximgproc::fastGlobalSmootherFilter(grey, both, smoothed, options.smootherLambda,
                                         options.smootherSigmaColor);
  std::vector<cv::Mat> parts;
  cv::split(smoothed, parts);
  cv::Mat sky = options.detectSky
                    ? skyMask(guide, sampleMask, distancePx, sinElevation, options.sky)
                    : cv::Mat();
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      size_t i = static_cast<size_t>(y) * width + x;
      if (!sky.empty() && sky.at<uchar>(y, x)) continue;  // stays +inf
      float d = parts[1].at<float>(y, x);
      float inverse = fill.at<float>(y, x) + (d > 0 ? parts[0].at<float>(y, x) / d : 0.0f);
      // A non-positive inverse depth would be beyond infinity: treat it as infinitely far.
      if (inverse > 0) depth[i] = 1.0f / inverse;
    }
  return depth;
}

std::vector<float> densifySparseDepth(const std::vector<SparseDepthSample>& samples,
                                      const Image& frame, const DensifyOptions& options) {
  cv::Mat rgb = rgbMat(frame);
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return densifySparseDepth(samples, bgr, options);
}

}  // namespace pluvia::sfm
