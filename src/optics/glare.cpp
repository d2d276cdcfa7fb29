#include "optics/glare.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace pluvia::optics {
namespace {

constexpr double kMaxDeg = 100.0;  // the formula's upper bound
// The pyramid stops when its coarsest level's longer side would be under this many pixels.
constexpr int kCoarsestSidePx = 1;
// The blurred copy of each level: a Gaussian of 1 px there (half an octave past the level).
constexpr double kLevelBlurPx = 1.0;
constexpr int kProfileBins = 48;

cv::Mat levelBlur(const cv::Mat& level) {
  cv::Mat out;
  cv::GaussianBlur(level, out, cv::Size(7, 7), kLevelBlurPx, kLevelBlurPx, cv::BORDER_CONSTANT);
  return out;
}

// The pyramid's filter, [1 4 6 4 1] / 16 (cv::pyrDown's), with zeros past the frame's edges so
// that light leaving the frame is lost, as it is with the true kernel.
cv::Mat binomial(const cv::Mat& image, double gain) {
  const cv::Mat k = (cv::Mat_<float>(5, 1) << 1, 4, 6, 4, 1) / 16.0f;
  cv::Mat out;
  cv::sepFilter2D(image, out, -1, k, k * float(gain), cv::Point(-1, -1), 0.0, cv::BORDER_CONSTANT);
  return out;
}

// The source reduced level by level: levels[0] itself, levels[j] the filtered levels[j - 1] at
// every other pixel. From level kPadLevel on, the frame sits in a margin of zeros half its size
// on each side, so that the wide blurs of the coarser levels spread past the frame's edges as
// the true kernel does rather than bouncing off them (reflecting or zero borders at a level a
// few pixels across would pile the far veil up at the edges); the fine levels, whose blurs span
// a few pixels, need no margin.
constexpr int kPadLevel = 3;

struct Pyramid {
  std::vector<cv::Mat> levels;
  cv::Rect frameAtPadLevel;  // where the frame is in the padded levels[kPadLevel]
};

Pyramid reduce(const cv::Mat& source, int count) {
  Pyramid p;
  p.levels.push_back(source);
  for (int j = 1; j <= count; ++j) {
    if (j - 1 == kPadLevel) {
      cv::Mat& level = p.levels.back();
      const int mx = (level.cols + 1) / 2, my = (level.rows + 1) / 2;
      p.frameAtPadLevel = cv::Rect(mx, my, level.cols, level.rows);
      cv::Mat padded;
      cv::copyMakeBorder(level, padded, my, my, mx, mx, cv::BORDER_CONSTANT, cv::Scalar::all(0));
      level = padded;
    }
    const cv::Mat filtered = binomial(p.levels.back(), 1.0);
    cv::Mat next((filtered.rows + 1) / 2, (filtered.cols + 1) / 2, filtered.type());
    const size_t pixelBytes = filtered.elemSize();
    for (int y = 0; y < next.rows; ++y)
      for (int x = 0; x < next.cols; ++x)
        std::memcpy(next.ptr(y) + x * pixelBytes, filtered.ptr(2 * y) + 2 * x * pixelBytes,
                    pixelBytes);
    p.levels.push_back(next);
  }
  return p;
}

// Brings `coarse` (level j) up to level `to` (< j) with cv::pyrUp, an interpolation, its margin
// cut off on the way down to the unpadded levels.
cv::Mat expand(cv::Mat coarse, int j, int to, const Pyramid& p) {
  for (int k = j - 1; k >= to; --k) {
    if (k + 1 == kPadLevel) coarse = coarse(p.frameAtPadLevel).clone();
    cv::Mat up;
    cv::pyrUp(coarse, up, p.levels[size_t(k)].size());
    coarse = up;
  }
  return coarse;
}

// Each pixel's log-spaced annulus around (cx, cy): bin b covers radii [edges[b], edges[b + 1]);
// -1 outside them.
std::vector<int> annulusOfPixel(cv::Size size, int cx, int cy, const std::vector<double>& edges) {
  std::vector<int> bins(size_t(size.area()), -1);
  const double logLo = std::log(edges.front()), logStep = std::log(edges[1] / edges[0]);
  const int count = int(edges.size()) - 1;
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const double r = std::hypot(x - cx, y - cy);
      if (r < edges.front() || r >= edges.back()) continue;
      bins[size_t(y) * size.width + x] = std::min(count - 1, int((std::log(r) - logLo) / logStep));
    }
  return bins;
}

// Mean of `image` (CV_32F or CV_64F, one channel) over each annulus; NaN for an empty one.
std::vector<double> radialMeans(const cv::Mat& image, const std::vector<int>& bins, int count) {
  std::vector<double> sum(size_t(count), 0.0);
  std::vector<int> n(size_t(count), 0);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const int b = bins[size_t(y) * image.cols + x];
      if (b < 0) continue;
      sum[size_t(b)] += image.depth() == CV_64F ? image.at<double>(y, x) : image.at<float>(y, x);
      ++n[size_t(b)];
    }
  for (size_t b = 0; b < sum.size(); ++b) sum[b] = n[b] ? sum[b] / n[b] : NAN;
  return sum;
}

// Non-negative least squares min |A w - b|^2, w >= 0, by cyclic coordinate descent on the
// normal equations (convex: it converges to the optimum; the problem has ~20 unknowns).
std::vector<double> nonNegativeLeastSquares(const cv::Mat& A, const cv::Mat& b) {
  const cv::Mat G = A.t() * A, h = A.t() * b;
  const int n = A.cols;
  std::vector<double> w(size_t(n), 0.0);
  for (int sweep = 0; sweep < 20000; ++sweep) {
    double change = 0.0;
    for (int i = 0; i < n; ++i) {
      if (!(G.at<double>(i, i) > 0.0)) continue;
      double gradient = -h.at<double>(i);
      for (int k = 0; k < n; ++k) gradient += G.at<double>(i, k) * w[size_t(k)];
      const double next = std::max(0.0, w[size_t(i)] - gradient / G.at<double>(i, i));
      change = std::max(change, std::abs(next - w[size_t(i)]));
      w[size_t(i)] = next;
    }
    if (change < 1e-12) break;
  }
  return w;
}

}  // namespace

double cieGlarePsf(double thetaDeg, double ageYears, double pigment) {
  const double t = std::clamp(thetaDeg, kGlareMinDeg, kMaxDeg);
  const double age = 1.0 + std::pow(ageYears / 62.5, 4.0);
  return 10.0 / (t * t * t) + (5.0 / (t * t) + 0.1 * pigment / t) * age + 0.0025 * pigment;
}

double glareKernelWeight(double radiusPx, double focalPx) {
  const double theta = std::atan(radiusPx / focalPx);
  const double c = std::cos(theta);
  return cieGlarePsf(theta * 180.0 / M_PI) * c * c * c / (focalPx * focalPx);
}

Image glareReference(const Image& source, double focalPx) {
  const int w = source.width, h = source.height;
  const int kw = 2 * w - 1, kh = 2 * h - 1;
  const int pw = cv::getOptimalDFTSize(w + kw - 1), ph = cv::getOptimalDFTSize(h + kh - 1);
  cv::Mat kernel = cv::Mat::zeros(ph, pw, CV_64F);
  double scattered = 0.0;
  for (int y = 0; y < kh; ++y)
    for (int x = 0; x < kw; ++x) {
      if (x == w - 1 && y == h - 1) continue;
      const double k = glareKernelWeight(std::hypot(x - (w - 1), y - (h - 1)), focalPx);
      kernel.at<double>(y, x) = k;
      scattered += k;
    }
  kernel.at<double>(h - 1, w - 1) = 1.0 - scattered;
  cv::Mat kernelSpectrum;
  cv::dft(kernel, kernelSpectrum);
  Image out(w, h);
  for (int c = 0; c < 3; ++c) {
    cv::Mat channel = cv::Mat::zeros(ph, pw, CV_64F);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) channel.at<double>(y, x) = source.pixel(x, y)[c];
    cv::Mat spectrum, full;
    cv::dft(channel, spectrum);
    cv::mulSpectrums(spectrum, kernelSpectrum, spectrum, 0);
    cv::dft(spectrum, full, cv::DFT_INVERSE | cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) out.pixel(x, y)[c] = float(full.at<double>(y + h - 1, x + w - 1));
  }
  return out;
}

GlarePyramid::GlarePyramid(int width, int height, double focalPx)
    : width_(width), height_(height), focalPx_(focalPx) {
  while ((std::max(width, height) >> (levels_ + 1)) >= kCoarsestSidePx) ++levels_;
  // The bases' impulse responses, measured on a canvas twice the frame's size (a source in a
  // corner reaches the opposite one) with a unit source at its centre and one pixel off it
  // (the pyramid is not quite shift-invariant: the two are averaged).
  const cv::Size canvas(2 * width, 2 * height);
  const int cx = width, cy = height;
  std::vector<double> edges(kProfileBins + 1);
  for (int b = 0; b <= kProfileBins; ++b)
    edges[size_t(b)] = 0.5 * std::pow(std::hypot(width, height) / 0.5, double(b) / kProfileBins);
  // Basis order: blurred level 0, then plain and blurred of levels 1..levels.
  const int bases = 2 * levels_ + 1;
  std::vector<std::vector<double>> profile(size_t(bases), std::vector<double>(kProfileBins, 0.0));
  for (int offset = 0; offset < 2; ++offset) {
    cv::Mat delta = cv::Mat::zeros(canvas, CV_32F);
    delta.at<float>(cy + offset, cx + offset) = 1.0f;
    const std::vector<int> bins = annulusOfPixel(canvas, cx + offset, cy + offset, edges);
    const Pyramid pyramid = reduce(delta, levels_);
    const std::vector<cv::Mat>& reduced = pyramid.levels;
    int m = 0;
    for (int j = 0; j <= levels_; ++j)
      for (int blurred = j == 0 ? 1 : 0; blurred < 2; ++blurred, ++m) {
        const cv::Mat basis =
            expand(blurred ? levelBlur(reduced[size_t(j)]) : reduced[size_t(j)], j, 0, pyramid);
        const std::vector<double> means = radialMeans(basis, bins, kProfileBins);
        for (int b = 0; b < kProfileBins; ++b)
          profile[size_t(m)][size_t(b)] += 0.5 * means[size_t(b)];
      }
  }
  // The true kernel's mean over the same annuli, and the share it scatters over the canvas.
  cv::Mat truth(canvas, CV_64F);
  for (int y = 0; y < canvas.height; ++y)
    for (int x = 0; x < canvas.width; ++x) {
      const double r = std::hypot(x - cx, y - cy);
      truth.at<double>(y, x) = r > 0.0 ? glareKernelWeight(r, focalPx) : 0.0;
      trueScattered_ += truth.at<double>(y, x);
    }
  const std::vector<double> trueMeans =
      radialMeans(truth, annulusOfPixel(canvas, cx, cy, edges), kProfileBins);
  // Fit: each annulus's relative error counts alike.
  std::vector<int> rows;
  for (int b = 0; b < kProfileBins; ++b)
    if (std::isfinite(trueMeans[size_t(b)]) && trueMeans[size_t(b)] > 0.0) rows.push_back(b);
  cv::Mat A(int(rows.size()), bases, CV_64F), target(int(rows.size()), 1, CV_64F);
  for (size_t i = 0; i < rows.size(); ++i) {
    const size_t b = size_t(rows[i]);
    for (int m = 0; m < bases; ++m) A.at<double>(int(i), m) = profile[size_t(m)][b] / trueMeans[b];
    target.at<double>(int(i)) = 1.0;
  }
  const std::vector<double> w = nonNegativeLeastSquares(A, target);
  plainWeight_.assign(size_t(levels_ + 1), 0.0);
  blurredWeight_.assign(size_t(levels_ + 1), 0.0);
  int m = 0;
  for (int j = 0; j <= levels_; ++j)
    for (int blurred = j == 0 ? 1 : 0; blurred < 2; ++blurred, ++m) {
      (blurred ? blurredWeight_ : plainWeight_)[size_t(j)] = w[size_t(m)];
      fittedScattered_ += w[size_t(m)];
    }
  // What the fit leaves at the source's pixel: the unscattered light.
  plainWeight_[0] = 1.0 - fittedScattered_;
  for (int b : rows) {
    radiiPx_.push_back(std::sqrt(edges[size_t(b)] * edges[size_t(b) + 1]));
    trueProfile_.push_back(trueMeans[size_t(b)]);
    double fitted = 0.0;
    for (int k = 0; k < bases; ++k) fitted += w[size_t(k)] * profile[size_t(k)][size_t(b)];
    fittedProfile_.push_back(fitted);
  }
}

Image GlarePyramid::convolve(const Image& source) const {
  const Pyramid pyramid = reduce(rgbMat(source), levels_);
  const std::vector<cv::Mat>& reduced = pyramid.levels;
  cv::Mat sum;
  for (int j = levels_; j >= 0; --j) {
    cv::Mat here = reduced[size_t(j)] * plainWeight_[size_t(j)];
    if (blurredWeight_[size_t(j)] > 0.0)
      here += levelBlur(reduced[size_t(j)]) * blurredWeight_[size_t(j)];
    if (!sum.empty()) here += expand(sum, j + 1, j, pyramid);
    sum = here;
  }
  return imageFromMat(sum);
}

}  // namespace pluvia::optics
