#include "derain/dense_flow.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "util/error.h"

namespace pluvia::derain {

namespace {
constexpr double kResidualTrimFraction = 0.10;
}  // namespace

double trimmedMeanAbsDifference(const cv::Mat1f& a, const cv::Mat1f& b, const cv::Mat1b& mask) {
  std::vector<float> differences;
  for (int y = 0; y < a.rows; ++y) {
    for (int x = 0; x < a.cols; ++x) {
      if (mask(y, x)) differences.push_back(std::abs(a(y, x) - b(y, x)));
    }
  }
  const size_t kept = size_t(std::ceil((1.0 - kResidualTrimFraction) * differences.size()));
  if (kept == 0) return std::numeric_limits<double>::infinity();
  std::nth_element(differences.begin(), differences.begin() + (kept - 1), differences.end());
  double sum = 0.0;
  for (size_t i = 0; i < kept; ++i) sum += differences[i];
  return sum / double(kept);
}

cv::Mat2f landingPoints(const cv::Mat2f& flow) {
  cv::Mat2f out(flow.size());
  for (int y = 0; y < flow.rows; ++y) {
    for (int x = 0; x < flow.cols; ++x) out(y, x) = flow(y, x) + cv::Vec2f(float(x), float(y));
  }
  return out;
}

cv::Mat1b inBounds(const cv::Mat2f& points) {
  cv::Mat1b out(points.size());
  const float maxX = float(points.cols - 1), maxY = float(points.rows - 1);
  for (int y = 0; y < points.rows; ++y) {
    for (int x = 0; x < points.cols; ++x) {
      const cv::Vec2f p = points(y, x);
      out(y, x) = (p[0] >= 0.0f && p[0] <= maxX && p[1] >= 0.0f && p[1] <= maxY) ? 255 : 0;
    }
  }
  return out;
}

cv::Mat1b forwardBackwardConsistent(const cv::Mat2f& forward, const cv::Mat2f& backward,
                                    const cv::Mat2f& points, double tolerancePx, double relative) {
  cv::Mat2f back;
  cv::remap(backward, back, points, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  cv::Mat1b out(forward.size());
  for (int y = 0; y < forward.rows; ++y) {
    for (int x = 0; x < forward.cols; ++x) {
      const double error = cv::norm(forward(y, x) + back(y, x), cv::NORM_L2SQR);
      const double length =
          cv::norm(forward(y, x), cv::NORM_L2SQR) + cv::norm(back(y, x), cv::NORM_L2SQR);
      out(y, x) = error < relative * relative * length + tolerancePx * tolerancePx ? 255 : 0;
    }
  }
  return out;
}

cv::Mat remapCubic(const cv::Mat& image, const cv::Mat2f& points) {
  cv::Mat out;
  cv::remap(image, out, points, cv::noArray(), cv::INTER_CUBIC, cv::BORDER_REPLICATE);
  return out;
}

bool denseFlowMeasures(cv::Size frameSize) {
  return std::max(frameSize.width, frameSize.height) >= kDenseFlowMinSidePx;
}

void requireDenseFlowSize(cv::Size frameSize, const std::string& what) {
  if (!denseFlowMeasures(frameSize))
    throw Error(
        fmt::format("{} needs frames of at least {} px on a side to follow their motion, "
                    "and these are {}x{} px",
                    what, kDenseFlowMinSidePx, frameSize.width, frameSize.height));
}

cv::Ptr<cv::DISOpticalFlow> makeDenseFlow() {
  return cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_MEDIUM);
}

}  // namespace pluvia::derain
