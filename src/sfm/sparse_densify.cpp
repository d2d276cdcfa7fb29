#include "sfm/sparse_densify.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/edge_filter.hpp>

namespace pluvia {
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
// plane, since inverse depth is affine in the image over a plane). Pixels outside the samples'
// convex hull keep `outside`.
cv::Mat delaunayFill(const std::vector<cv::Point2f>& sites, const std::vector<float>& values,
                     const cv::Mat& outside) {
  cv::Mat out = outside.clone();
  if (sites.size() < 3) return out;
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
      }
  }
  return out;
}

// Bright, smooth pixels far from samples and connected to the top row.
cv::Mat skyMask(const cv::Mat& grey, const cv::Mat& sampleMask, const DensifyOptions& options) {
  cv::Mat notSample = sampleMask == 0;
  cv::Mat distancePx;
  cv::distanceTransform(notSample, distancePx, cv::DIST_L2, 3);
  const double diagonal = std::hypot(grey.cols, grey.rows);
  cv::Mat gx, gy, gradient;
  cv::Sobel(grey, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
  cv::Sobel(grey, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
  cv::magnitude(gx, gy, gradient);
  cv::blur(gradient, gradient, cv::Size(9, 9));
  std::vector<uchar> levels(grey.begin<uchar>(), grey.end<uchar>());
  std::nth_element(levels.begin(), levels.begin() + levels.size() / 2, levels.end());
  const uchar medianGrey = levels[levels.size() / 2];
  cv::Mat candidate = (distancePx > options.skyMinDistanceFraction * diagonal) &
                      (grey > medianGrey) & (gradient < options.skyMaxGradient);
  cv::Mat labels;
  int count = cv::connectedComponents(candidate, labels, 4, CV_32S);
  std::vector<char> touchesTop(count, 0);
  for (int x = 0; x < labels.cols; ++x) {
    int label = labels.at<int>(0, x);
    if (label > 0) touchesTop[label] = 1;
  }
  cv::Mat sky = cv::Mat::zeros(grey.size(), CV_8U);
  for (int y = 0; y < labels.rows; ++y)
    for (int x = 0; x < labels.cols; ++x)
      if (touchesTop[labels.at<int>(y, x)] && labels.at<int>(y, x) > 0) sky.at<uchar>(y, x) = 255;
  return sky;
}

}  // namespace

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

std::vector<float> densifySparseDepth(const std::vector<SparseDepthSample>& samples,
                                      const cv::Mat& guide, const DensifyOptions& options) {
  const int width = guide.cols, height = guide.rows;
  std::vector<float> depth(static_cast<size_t>(width) * height,
                           std::numeric_limits<float>::infinity());
  cv::Mat sum = cv::Mat::zeros(height, width, CV_32F), weight = sum.clone();
  int used = 0;
  std::vector<cv::Point2f> sites;
  std::vector<float> siteValues;
  for (const auto& s : samples) {
    int x = static_cast<int>(std::floor(s.xPx)), y = static_cast<int>(std::floor(s.yPx));
    if (x < 0 || y < 0 || x >= width || y >= height || !(s.depthMeters > 0) ||
        !std::isfinite(s.depthMeters))
      continue;
    sum.at<float>(y, x) += static_cast<float>(1.0 / s.depthMeters);
    weight.at<float>(y, x) += 1.0f;
    sites.emplace_back(static_cast<float>(s.xPx), static_cast<float>(s.yPx));
    siteValues.push_back(static_cast<float>(1.0 / s.depthMeters));
    ++used;
  }
  if (used == 0) return depth;
  // Several samples on one pixel count as one, so dense clusters do not outweigh the prior.
  cv::Mat sampleMask = weight > 0;
  cv::Mat average;
  cv::divide(sum, cv::max(weight, 1.0f), average);
  cv::Mat unitWeight;
  sampleMask.convertTo(unitWeight, CV_32F, 1.0 / 255.0);

  cv::Mat fill = delaunayFill(sites, siteValues, pushPull(average, unitWeight));
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
  cv::Mat sky = options.detectSky ? skyMask(grey, sampleMask, options) : cv::Mat();
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

}  // namespace pluvia
