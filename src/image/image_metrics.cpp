#include "image/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace pluvia {
namespace {

void checkPair(const cv::Mat& a, const cv::Mat& b, const char* what) {
  if (a.empty() || a.size() != b.size() || a.type() != b.type() || a.depth() != CV_32F) {
    throw std::invalid_argument(std::string(what) +
                                ": the images must be non-empty CV_32F of the same size and type");
  }
}

}  // namespace

double psnrDb(const cv::Mat& result, const cv::Mat& truth) {
  checkPair(result, truth, "psnrDb");
  double sum = 0.0;
  const int values = result.cols * result.channels();
  for (int y = 0; y < result.rows; ++y) {
    const float* a = result.ptr<float>(y);
    const float* b = truth.ptr<float>(y);
    for (int i = 0; i < values; ++i) {
      const double d = double(a[i]) - double(b[i]);
      sum += d * d;
    }
  }
  const double mse = sum / (double(result.total()) * result.channels());
  if (mse == 0.0) return std::numeric_limits<double>::infinity();
  return -10.0 * std::log10(mse);
}

double ssim(const cv::Mat& result, const cv::Mat& truth) {
  checkPair(result, truth, "ssim");
  constexpr double kC1 = (0.01 * 1.0) * (0.01 * 1.0), kC2 = (0.03 * 1.0) * (0.03 * 1.0);
  const cv::Size window(11, 11);
  constexpr double kSigma = 1.5;
  std::vector<cv::Mat> xs, ys;
  cv::split(result, xs);
  cv::split(truth, ys);
  // The windows wholly inside the image: their centres leave a 5-pixel border.
  const int border = (result.rows >= 11 && result.cols >= 11) ? 5 : 0;
  const cv::Rect inside(border, border, result.cols - 2 * border, result.rows - 2 * border);
  double total = 0.0;
  for (size_t c = 0; c < xs.size(); ++c) {
    cv::Mat x, y;
    xs[c].convertTo(x, CV_64F);
    ys[c].convertTo(y, CV_64F);
    auto blur = [&](const cv::Mat& m) {
      cv::Mat out;
      cv::GaussianBlur(m, out, window, kSigma, kSigma, cv::BORDER_REFLECT);
      return out;
    };
    const cv::Mat muX = blur(x), muY = blur(y);
    const cv::Mat xx = blur(x.mul(x)), yy = blur(y.mul(y)), xy = blur(x.mul(y));
    double sum = 0.0;
    for (int r = inside.y; r < inside.y + inside.height; ++r) {
      const double* mx = muX.ptr<double>(r);
      const double* my = muY.ptr<double>(r);
      const double* sxx = xx.ptr<double>(r);
      const double* syy = yy.ptr<double>(r);
      const double* sxy = xy.ptr<double>(r);
      for (int col = inside.x; col < inside.x + inside.width; ++col) {
        const double varX = sxx[col] - mx[col] * mx[col];
        const double varY = syy[col] - my[col] * my[col];
        const double cov = sxy[col] - mx[col] * my[col];
        sum += ((2.0 * mx[col] * my[col] + kC1) * (2.0 * cov + kC2)) /
               ((mx[col] * mx[col] + my[col] * my[col] + kC1) * (varX + varY + kC2));
      }
    }
    total += sum / double(inside.area());
  }
  return total / double(xs.size());
}

}  // namespace pluvia
