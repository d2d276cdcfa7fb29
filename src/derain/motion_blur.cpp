#include "derain/motion_blur.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "derain/dense_flow.h"
#include "rain/drop_physics.h"
#include "util/error.h"

namespace pluvia::derain {

namespace {

constexpr int kMaxWidthPx = 1024;
constexpr double kMaxSpeedPx = 40.0;  // faster edges are left out: flow and profile both fail
constexpr double kProfileStepPx = 0.5;
// Edges: the strongest 8 % of gradients, thinned to their ridge; at most this many a frame.
constexpr double kEdgeQuantile = 0.92;
constexpr size_t kMaxEdgesPerFrame = 40000;
// A bin of speeds across the edge is fitted when it holds this many profiles.
constexpr int kMinBinEdges = 20;
constexpr double kMaxFrameSpread = 2.0;
constexpr std::array<double, 8> kSpeedBinEdgesPx{0.0, 0.75, 1.5, 3.0, 6.0, 12.0, 24.0, 40.0};

struct EdgeSample {
  double acrossPx;  // |v . n|, px a frame
  double widthPx;   // contrast over steepest slope
  int frame;
};

float bilinear(const cv::Mat1f& image, double x, double y) {
  x = std::clamp(x, 0.0, double(image.cols - 1));
  y = std::clamp(y, 0.0, double(image.rows - 1));
  const int x0 = std::min(int(x), image.cols - 2 < 0 ? 0 : image.cols - 2);
  const int y0 = std::min(int(y), image.rows - 2 < 0 ? 0 : image.rows - 2);
  const int x1 = std::min(x0 + 1, image.cols - 1), y1 = std::min(y0 + 1, image.rows - 1);
  const double ax = x - x0, ay = y - y0;
  return float((1 - ay) * ((1 - ax) * image(y0, x0) + ax * image(y0, x1)) +
               ay * ((1 - ax) * image(y1, x0) + ax * image(y1, x1)));
}

cv::Vec2f bilinear(const cv::Mat2f& flow, double x, double y) {
  const int xi = std::clamp(int(std::lround(x)), 0, flow.cols - 1);
  const int yi = std::clamp(int(std::lround(y)), 0, flow.rows - 1);
  return flow(yi, xi);
}

// The width of the edge at (x, y) across its unit normal n (pointing up the slope), or NaN when
// the profile is no lone step: another edge or a line within reach (its total variation over
// 1.25 times its contrast), or no rise at all.
double edgeWidthPx(const cv::Mat1f& grey, double x, double y, double nx, double ny,
                   double reachPx) {
  const int half = int(std::ceil(reachPx / kProfileStepPx));
  std::vector<double> profile(size_t(2 * half + 1));
  for (int i = -half; i <= half; ++i)
    profile[size_t(i + half)] =
        bilinear(grey, x + nx * i * kProfileStepPx, y + ny * i * kProfileStepPx);
  const size_t n = profile.size();
  const double contrast = 0.5 * (profile[n - 1] + profile[n - 2]) - 0.5 * (profile[0] + profile[1]);
  if (!(contrast > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  double variation = 0.0;
  for (size_t i = 1; i < n; ++i) variation += std::abs(profile[i] - profile[i - 1]);
  if (variation > 1.25 * contrast) return std::numeric_limits<double>::quiet_NaN();
  // The steepest slope over 1 px, within 2 px of the ridge pixel.
  double steepest = 0.0;
  const int within = int(2.0 / kProfileStepPx);
  for (int i = -within; i <= within; ++i) {
    const size_t c = size_t(i + half);
    if (c < 1 || c + 1 >= n) continue;
    steepest = std::max(steepest, (profile[c + 1] - profile[c - 1]) / (2.0 * kProfileStepPx));
  }
  if (!(steepest > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return contrast / steepest;
}

// 8-bit greys for the flow: the linear grey encoded with a 1/2.2 power over its 99.5th
// percentile, so the flow sees the shadows' texture as a display does.
cv::Mat1b flowCodes(const cv::Mat1f& grey, float white) {
  cv::Mat1b codes(grey.size());
  for (int y = 0; y < grey.rows; ++y)
    for (int x = 0; x < grey.cols; ++x)
      codes(y, x) = cv::saturate_cast<uint8_t>(
          255.0 * std::pow(std::clamp(grey(y, x) / white, 0.0f, 1.0f), 1.0 / 2.2));
  return codes;
}

float quantile(std::vector<float> values, double q) {
  if (values.empty()) return 0.0f;
  const size_t k = std::min(values.size() - 1, size_t(q * double(values.size())));
  std::nth_element(values.begin(), values.begin() + ptrdiff_t(k), values.end());
  return values[k];
}

// The edge profiles of frame `middle` (1 .. size - 2), its motion the half difference of the
// flows to the frames either side.
void sampleFrame(const std::vector<cv::Mat1f>& greys, const std::vector<cv::Mat1b>& codes,
                 int middle, std::vector<EdgeSample>& samples) {
  const cv::Mat1f& grey = greys[size_t(middle)];
  cv::Mat2f forward, backward;
  const cv::Ptr<cv::DISOpticalFlow> dis = makeDenseFlow();
  dis->calc(codes[size_t(middle)], codes[size_t(middle + 1)], forward);
  dis->calc(codes[size_t(middle)], codes[size_t(middle - 1)], backward);
  cv::Mat1f gx, gy;
  cv::Sobel(grey, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
  cv::Sobel(grey, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
  cv::Mat1f magnitude;
  cv::magnitude(gx, gy, magnitude);
  const float threshold =
      quantile(std::vector<float>(magnitude.begin(), magnitude.end()), kEdgeQuantile);
  if (!(threshold > 0.0f)) return;
  const int border = 4;
  size_t kept = 0;
  for (int y = border; y < grey.rows - border; ++y) {
    for (int x = border; x < grey.cols - border; ++x) {
      const float m = magnitude(y, x);
      if (m < threshold) continue;
      const double nx = gx(y, x) / m, ny = gy(y, x) / m;
      // The ridge: no stronger gradient one pixel up or down the normal.
      const int dx = int(std::lround(nx)), dy = int(std::lround(ny));
      if (magnitude(y + dy, x + dx) > m || magnitude(y - dy, x - dx) >= m) continue;
      const cv::Vec2f f = forward(y, x), b = backward(y, x);
      const cv::Vec2f v = 0.5f * (f - b);
      const double speed = cv::norm(v);
      if (speed > kMaxSpeedPx) continue;
      // Steady motion over the three frames, and the same motion on both sides of the edge
      // (an occluding edge's sides move apart: its flow is neither's).
      if (cv::norm(f + b) > 0.25 * speed + 0.5) continue;
      const double reach = 0.5 * std::abs(v[0] * nx + v[1] * ny) + 4.0;
      const cv::Vec2f before =
          bilinear(forward, x - nx * 3, y - ny * 3) - bilinear(backward, x - nx * 3, y - ny * 3);
      const cv::Vec2f after =
          bilinear(forward, x + nx * 3, y + ny * 3) - bilinear(backward, x + nx * 3, y + ny * 3);
      if (cv::norm(0.5f * (after - before)) > 0.25 * speed + 0.5) continue;
      const double width = edgeWidthPx(grey, x, y, nx, ny, reach);
      if (!std::isfinite(width) || width > 2.0 * reach) continue;
      samples.push_back({std::abs(v[0] * nx + v[1] * ny), width, middle});
      if (++kept >= kMaxEdgesPerFrame) return;
    }
  }
}

struct SpeedBin {
  double acrossPx, widthPx;
  int count;
};

std::vector<SpeedBin> speedBins(const std::vector<EdgeSample>& samples, int frame) {
  std::vector<SpeedBin> bins;
  for (size_t b = 0; b + 1 < kSpeedBinEdgesPx.size(); ++b) {
    std::vector<float> across, widths;
    for (const EdgeSample& s : samples) {
      if (frame >= 0 && s.frame != frame) continue;
      if (s.acrossPx < kSpeedBinEdgesPx[b] || s.acrossPx >= kSpeedBinEdgesPx[b + 1]) continue;
      across.push_back(float(s.acrossPx));
      widths.push_back(float(s.widthPx));
    }
    if (int(across.size()) < kMinBinEdges) continue;
    bins.push_back({quantile(across, 0.5), quantile(widths, 0.5), int(across.size())});
  }
  return bins;
}

// The profile's own blur, px^2: it is sampled bilinearly (a triangle kernel, variance 1/6 px^2)
// and its slope taken over 1 px (a box, 1/12), the steepest of several, which reads it a little
// steep. On synthetic still edges of known blur (tests/derain/test_motion_blur.cpp: sigma 0.29
// 1.53 px) the width over sqrt(2 pi) reads sqrt(sigma^2 + 0.2) from 0.76 px up (0.85 for 0.76,
// 1.59 for 1.53) and more below (0.54 for 0.29). That 0.2 is taken off in quadrature: within
// 15 % from 0.76 px up, and a sharper plate reads sharper still (0.30 for 0.42).
constexpr double kProfileVariancePx2 = 0.2;

// A measured edge width, over sqrt(2 pi), as the sigma of the edge's own Gaussian blur.
double edgeSigmaPx(double widthPx) {
  const double sigma = widthPx / std::sqrt(2.0 * M_PI);
  return std::sqrt(std::max(0.0, sigma * sigma - kProfileVariancePx2));
}

// The still edges' blur: those of the slowest bin, whose ramp f |v . n| is under 0.75 f px (a
// sixth of their blur's width at sigma 1 px and a 180-degree shutter), so that each width is
// sqrt(2 pi) sigma. 0 with fewer than kMinStillEdges.
double stillEdgeBlurPx(const std::vector<EdgeSample>& samples) {
  std::vector<float> widths;
  for (const EdgeSample& s : samples)
    if (s.acrossPx < kSpeedBinEdgesPx[1]) widths.push_back(float(s.widthPx));
  if (int(widths.size()) < kMinStillEdges) return 0.0;
  return edgeSigmaPx(quantile(widths, 0.5));
}

struct Fit {
  double shutterFraction = 0.0, sigmaPx = 0.0;
  bool ok = false;
};

// The (f, sigma) whose widths meet the bins' median widths best (log widths, each bin weighted
// by the root of its count), over a grid: f from 0.01 to 1 (2 % steps), sigma 0.25 to 4 px.
Fit fitBins(const std::vector<SpeedBin>& bins) {
  int still = 0, moving = 0;
  for (const SpeedBin& b : bins) (b.acrossPx < kMovingPx ? still : moving) += 1;
  if (still < 1 || moving < 1) return {};
  Fit best;
  double bestCost = std::numeric_limits<double>::infinity();
  for (double f = 0.01; f <= 1.0 + 1e-9; f *= 1.02) {
    for (double sigma = 0.25; sigma <= 4.0 + 1e-9; sigma += 0.025) {
      double cost = 0.0;
      for (const SpeedBin& b : bins) {
        const double r = std::log(b.widthPx / blurredEdgeWidthPx(f * b.acrossPx, sigma));
        cost += std::sqrt(double(b.count)) * r * r;
      }
      if (cost < bestCost) {
        bestCost = cost;
        best = {std::min(f, 1.0), sigma, true};
      }
    }
  }
  return best;
}

}  // namespace

double dropSecondsPerDiameter() {
  static const double seconds = 1.5e-3 / rain::terminalVelocityMetersPerSecond(1.5);
  return seconds;
}

double shutterFromStreaksSeconds(double elongationByLight) {
  if (!(elongationByLight > 1.0)) return 0.0;
  return (elongationByLight - 1.0) * dropSecondsPerDiameter();
}

double blurredEdgeWidthPx(double rampPx, double sigmaPx) {
  const double s = std::max(sigmaPx, 1e-6);
  if (rampPx < 1e-3 * s) return std::sqrt(2.0 * M_PI) * s;
  return rampPx / std::erf(rampPx / (2.0 * std::sqrt(2.0) * s));
}

ShutterFromBlur measureShutterFromBlur(const std::vector<cv::Mat1f>& input) {
  if (input.size() < 3)
    throw Error(fmt::format("the shutter is measured on 3 or more frames, not {}", input.size()));
  for (const cv::Mat1f& g : input)
    if (g.size() != input.front().size())
      throw Error("the shutter is measured on frames of one size");
  std::vector<cv::Mat1f> greys;
  const double scale = std::min(1.0, double(kMaxWidthPx) / input.front().cols);
  for (const cv::Mat1f& g : input) {
    cv::Mat1f small, finite = g.clone();
    // A NaN or infinite sample (a float plate's) is no edge: black.
    for (float& v : finite)
      if (!std::isfinite(v)) v = 0.0f;
    if (scale < 1.0)
      cv::resize(finite, small, cv::Size(), scale, scale, cv::INTER_AREA);
    else
      small = finite;
    greys.push_back(small);
  }
  std::vector<float> all;
  for (const cv::Mat1f& g : greys) all.insert(all.end(), g.begin(), g.end());
  const float white = std::max(quantile(all, 0.995), 1e-6f);
  std::vector<cv::Mat1b> codes;
  for (const cv::Mat1f& g : greys) codes.push_back(flowCodes(g, white));
  if (!denseFlowMeasures(greys.front().size())) {
    ShutterFromBlur tooSmall;
    tooSmall.summary = fmt::format(
        "frames of {}x{} px are too small to follow their motion (needs {} px on a side)",
        greys.front().cols, greys.front().rows, kDenseFlowMinSidePx);
    return tooSmall;
  }

  std::vector<EdgeSample> samples;
  for (int middle = 1; middle + 1 < int(greys.size()); ++middle)
    sampleFrame(greys, codes, middle, samples);
  ShutterFromBlur result;
  result.edges = int(samples.size());
  for (const EdgeSample& s : samples) result.movingEdges += s.acrossPx >= kMovingPx ? 1 : 0;
  result.stillBlurPx = stillEdgeBlurPx(samples) / scale;
  if (result.movingEdges < kMinMovingEdges) {
    result.summary = fmt::format(
        "too little motion to measure: {} of {} edges move {:g} px a frame or more across "
        "themselves (needs {})",
        result.movingEdges, result.edges, kMovingPx, kMinMovingEdges);
    return result;
  }
  const std::vector<SpeedBin> bins = speedBins(samples, -1);
  const Fit fit = fitBins(bins);
  if (!fit.ok) {
    result.summary = fmt::format(
        "the {} moving edges span too few speeds to tell the shutter from the lens's blur",
        result.movingEdges);
    return result;
  }
  std::vector<double> perFrame;
  for (int middle = 1; middle + 1 < int(greys.size()); ++middle)
    if (const Fit f = fitBins(speedBins(samples, middle)); f.ok)
      perFrame.push_back(f.shutterFraction);
  std::sort(perFrame.begin(), perFrame.end());
  if (perFrame.size() >= 2) {
    result.lowFraction = perFrame[perFrame.size() / 4] / fit.shutterFraction;
    result.highFraction = perFrame[(3 * perFrame.size()) / 4] / fit.shutterFraction;
  }
  result.measured = true;
  result.shutterFraction = fit.shutterFraction;
  // A ramp under half the still blur cannot be seen: below that the fit only says "shorter",
  // and the shortest shutter it can tell from the fastest edges is kept, as an upper bound.
  double fastestPx = 0.0;
  for (const SpeedBin& b : bins) fastestPx = std::max(fastestPx, b.acrossPx);
  const double resolvable = std::min(1.0, 0.5 * fit.sigmaPx / fastestPx);
  result.upperBound = fit.shutterFraction < resolvable;
  if (result.upperBound) result.shutterFraction = resolvable;
  // Frames that disagree by more than a factor kMaxFrameSpread (the middle half of their own
  // fits) saw no steady blur: what moved was no rigid edge (splashes, swaying leaves, rain).
  if (!result.upperBound && result.lowFraction > 0.0 &&
      result.highFraction > kMaxFrameSpread * result.lowFraction) {
    result.measured = false;
    result.summary = fmt::format(
        "{} moving edges, but the frames alone disagree: the middle half of their fits spans "
        "{:.2f}-{:.2f} of the clip's (no steady blur: what moves is not rigid)",
        result.movingEdges, result.lowFraction, result.highFraction);
    return result;
  }
  result.sigmaPx = fit.sigmaPx;
  if (result.stillBlurPx == 0.0)
    result.stillBlurPx = edgeSigmaPx(std::sqrt(2.0 * M_PI) * fit.sigmaPx) / scale;
  result.summary = fmt::format(
      "{} edge profiles, {} of them moving across themselves {:g}-{:.0f} px a frame: the shutter "
      "open {}{:.1f} % of the frame ({}a {:.0f} deg shutter), a still edge blurred by {:.2f} px{}",
      result.edges, result.movingEdges, kMovingPx, fastestPx / scale,
      result.upperBound ? "at most " : "", 100.0 * result.shutterFraction,
      result.upperBound ? "the blur too short to see: at most " : "",
      360.0 * result.shutterFraction, fit.sigmaPx / scale,
      perFrame.size() >= 2 && !result.upperBound
          ? fmt::format(", frames alone {:.2f}-{:.2f} of it", result.lowFraction,
                        result.highFraction)
          : "");
  return result;
}

}  // namespace pluvia::derain
