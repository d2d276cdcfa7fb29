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
constexpr int kProfileBins = 48;
// The bases are measured up to this level on a canvas of kCanvasPx (a level-5 blur spans about
// 40 px: 5 of them fit in half the canvas), in kFineBins annuli; the true kernel is taken from
// the same pixels inside kNearPx of the source.
constexpr int kMeasuredLevel = 5;
constexpr int kCanvasPx = 512;
constexpr int kFineBins = 96;
constexpr double kNearPx = 8.0;

// The binomial [1 4 6 4 1] / 16 (cv::pyrDown's filter): a Gaussian of 1 px to within its 5
// taps, half the cost of cv::GaussianBlur's 7.
const cv::Mat& binomial() {
  static const cv::Mat k = (cv::Mat_<float>(5, 1) << 1, 4, 6, 4, 1) / 16.0f;
  return k;
}

cv::Mat levelBlur(const cv::Mat& level) {
  cv::Mat out;
  cv::sepFilter2D(level, out, -1, binomial(), binomial(), cv::Point(-1, -1), 0.0,
                  cv::BORDER_CONSTANT);
  return out;
}

// The source reduced level by level: levels[0] itself, levels[j] the binomial filter of levels[j
// - 1] at every other pixel, with zeros past the edges (cv::pyrDown reflects them: at the
// coarsest levels, a few pixels across, that folds the far veil back into the frame). From level
// kPadLevel on, the frame sits in a margin of zeros half its size on each side, so that the wide
// blurs of the coarser levels spread past the frame's edges as the true kernel does rather than
// bouncing off them (reflecting or zero borders at a level a few pixels across would pile the far
// veil up at the edges); the fine levels, whose blurs span a few pixels, need no margin.
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
    cv::Mat filtered;
    cv::sepFilter2D(p.levels.back(), filtered, -1, binomial(), binomial(), cv::Point(-1, -1), 0.0,
                    cv::BORDER_CONSTANT);
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

// The profile (values at increasing radii, NaN where unmeasured) at `r`, linear in log r; 0
// past its last radius.
double interpolateProfile(const std::vector<double>& radii, const std::vector<double>& values,
                          double r) {
  double lastR = 0.0, lastV = NAN;
  for (size_t i = 0; i < radii.size(); ++i) {
    if (!std::isfinite(values[i])) continue;
    if (radii[i] >= r) {
      if (!std::isfinite(lastV)) return values[i];
      const double t = std::log(r / lastR) / std::log(radii[i] / lastR);
      return lastV + t * (values[i] - lastV);
    }
    lastR = radii[i], lastV = values[i];
  }
  return 0.0;
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
  // The bases' impulse responses, measured up to level kMeasuredLevel on a small canvas with a
  // unit source at its centre and one pixel off it (the pyramid is not quite shift-invariant:
  // the two are averaged), in fine annuli. A coarser level's is the last measured one's spread
  // by 2 per level (the pyramid repeats itself: B_j(r) = B_m(r / s) / s^2, s = 2^(j - m)).
  const int measured = std::min(levels_, kMeasuredLevel);
  const cv::Size canvas(kCanvasPx, kCanvasPx);
  const int cx = kCanvasPx / 2, cy = kCanvasPx / 2;
  std::vector<double> fineEdges(kFineBins + 1), fineRadii(kFineBins);
  for (int b = 0; b <= kFineBins; ++b)
    fineEdges[size_t(b)] = 0.5 * std::pow(kCanvasPx / std::sqrt(2.0), double(b) / kFineBins);
  for (int b = 0; b < kFineBins; ++b)
    fineRadii[size_t(b)] = std::sqrt(fineEdges[size_t(b)] * fineEdges[size_t(b) + 1]);
  const int measuredBases = 2 * measured + 1;  // blurred level 0, plain and blurred 1..measured
  std::vector<std::vector<double>> fine(size_t(measuredBases), std::vector<double>(kFineBins, 0.0));
  for (int offset = 0; offset < 2; ++offset) {
    cv::Mat delta = cv::Mat::zeros(canvas, CV_32F);
    delta.at<float>(cy + offset, cx + offset) = 1.0f;
    const std::vector<int> bins = annulusOfPixel(canvas, cx + offset, cy + offset, fineEdges);
    const Pyramid pyramid = reduce(delta, measured);
    int m = 0;
    for (int j = 0; j <= measured; ++j)
      for (int blurred = j == 0 ? 1 : 0; blurred < 2; ++blurred, ++m) {
        const cv::Mat& level = pyramid.levels[size_t(j)];
        const cv::Mat basis = expand(blurred ? levelBlur(level) : level, j, 0, pyramid);
        const std::vector<double> means = radialMeans(basis, bins, kFineBins);
        for (int b = 0; b < kFineBins; ++b) fine[size_t(m)][size_t(b)] += 0.5 * means[size_t(b)];
      }
  }
  cv::Mat truth(canvas, CV_64F);
  for (int y = 0; y < canvas.height; ++y)
    for (int x = 0; x < canvas.width; ++x) {
      const double r = std::hypot(x - cx, y - cy);
      truth.at<double>(y, x) = r > 0.0 ? glareKernelWeight(r, focalPx) : 0.0;
    }
  const std::vector<double> fineTruth =
      radialMeans(truth, annulusOfPixel(canvas, cx, cy, fineEdges), kFineBins);
  // The fit's annuli, out to the frame's diagonal (a source in a corner reaches the opposite
  // one): each basis and the true kernel at their geometric centres, the measured pixel means
  // near the source (where pixels are few and their layout matters), the kernel's formula and
  // the spread bases beyond.
  const double rMax = std::hypot(width, height);
  std::vector<double> edges(kProfileBins + 1);
  for (int b = 0; b <= kProfileBins; ++b)
    edges[size_t(b)] = 0.5 * std::pow(rMax / 0.5, double(b) / kProfileBins);
  const int bases = 2 * levels_ + 1;
  auto basisAt = [&](int m, double r) {
    // Basis m: blurred level 0 (m = 0), then plain (odd) and blurred (even) of level (m + 1) / 2.
    const int j = (m + 1) / 2, blurred = m == 0 || m % 2 == 0;
    const int source = j <= measured ? m : 2 * measured - (blurred ? 0 : 1);
    const double spread = std::ldexp(1.0, std::max(0, j - measured));
    return interpolateProfile(fineRadii, fine[size_t(source)], r / spread) / (spread * spread);
  };
  std::vector<double> trueMeans, radii;
  std::vector<std::vector<double>> columns(static_cast<size_t>(bases));
  for (int b = 0; b < kProfileBins; ++b) {
    const double r = std::sqrt(edges[size_t(b)] * edges[size_t(b) + 1]);
    const double t =
        r < kNearPx ? interpolateProfile(fineRadii, fineTruth, r) : glareKernelWeight(r, focalPx);
    if (!(t > 0.0) || edges[size_t(b) + 1] < 1.0) continue;  // no pixel under 1 px but the source's
    radii.push_back(r);
    trueMeans.push_back(t);
    for (int m = 0; m < bases; ++m) columns[size_t(m)].push_back(basisAt(m, r));
  }
  // Fit: each annulus's relative error counts alike.
  cv::Mat A(int(radii.size()), bases, CV_64F), target(int(radii.size()), 1, CV_64F);
  for (size_t i = 0; i < radii.size(); ++i) {
    for (int m = 0; m < bases; ++m) A.at<double>(int(i), m) = columns[size_t(m)][i] / trueMeans[i];
    target.at<double>(int(i)) = 1.0;
  }
  const std::vector<double> w = nonNegativeLeastSquares(A, target);
  plainWeight_.assign(size_t(levels_ + 1), 0.0);
  blurredWeight_.assign(size_t(levels_ + 1), 0.0);
  double fittedSum = 0.0;
  int m = 0;
  for (int j = 0; j <= levels_; ++j)
    for (int blurred = j == 0 ? 1 : 0; blurred < 2; ++blurred, ++m) {
      (blurred ? blurredWeight_ : plainWeight_)[size_t(j)] = w[size_t(m)];
      fittedSum += w[size_t(m)];
    }
  // What the fit leaves at the source's pixel: the unscattered light.
  plainWeight_[0] = 1.0 - fittedSum;
  // The shares scattered within the frame's half-diagonal, both summed over the same annuli.
  const double rHalf = 0.5 * rMax;
  for (size_t i = 0; i < radii.size(); ++i) {
    double fitted = 0.0;
    for (int k = 0; k < bases; ++k) fitted += w[size_t(k)] * columns[size_t(k)][i];
    radiiPx_.push_back(radii[i]);
    trueProfile_.push_back(trueMeans[i]);
    fittedProfile_.push_back(fitted);
    if (radii[i] > rHalf) continue;
    const double lo = radii[i] / std::sqrt(edges[1] / edges[0]),
                 hi = radii[i] * std::sqrt(edges[1] / edges[0]);
    const double area = M_PI * (hi * hi - lo * lo);
    trueScattered_ += area * trueMeans[i];
    fittedScattered_ += area * fitted;
  }
}

cv::Mat GlarePyramid::convolve(const cv::Mat& rgb) const {
  const Pyramid pyramid = reduce(rgb, levels_);
  // Collapsed coarse to fine in place, few full-size buffers (allocating them costs as much as
  // the filtering at 1080p).
  cv::Mat sum;
  for (int j = levels_; j >= 0; --j) {
    const cv::Mat& level = pyramid.levels[size_t(j)];
    if (sum.empty())
      sum = level * plainWeight_[size_t(j)];
    else {
      sum = expand(sum, j + 1, j, pyramid);
      cv::scaleAdd(level, plainWeight_[size_t(j)], sum, sum);
    }
    if (blurredWeight_[size_t(j)] > 0.0) {
      cv::scaleAdd(levelBlur(level), blurredWeight_[size_t(j)], sum, sum);
    }
  }
  return sum;
}

Image GlarePyramid::convolve(const Image& source) const {
  return imageFromMat(convolve(rgbMat(source)));
}

}  // namespace pluvia::optics
