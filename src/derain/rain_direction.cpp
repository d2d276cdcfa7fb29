#include "derain/rain_direction.h"

#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "derain/frame_stack.h"

namespace pluvia::derain {
namespace {

// Spectral band searched, in cycles per pixel: below it lies the matte's large-scale layout,
// above it mostly noise and aliasing.
constexpr double kMinFrequency = 0.02;
constexpr double kMaxFrequency = 0.45;
constexpr double kCoarseStepDeg = 0.5;
constexpr double kFineStepDeg = 0.02;

// Power spectrum summed over the mattes, each mean-subtracted and Hann-windowed, with the zero
// frequency moved to the centre.
cv::Mat summedPowerSpectrum(const std::vector<cv::Mat>& mattes) {
  const cv::Size size = mattes[0].size();
  cv::Mat window;
  cv::createHanningWindow(window, size, CV_32F);
  const cv::Size padded(cv::getOptimalDFTSize(size.width), cv::getOptimalDFTSize(size.height));
  cv::Mat sum = cv::Mat::zeros(padded, CV_32F);
  for (const cv::Mat& matte : mattes) {
    cv::Mat centred = matte - cv::mean(matte)[0];
    cv::Mat input = cv::Mat::zeros(padded, CV_32F);
    cv::Mat windowed = centred.mul(window);
    windowed.copyTo(input(cv::Rect(0, 0, size.width, size.height)));
    cv::Mat spectrum;
    cv::dft(input, spectrum, cv::DFT_COMPLEX_OUTPUT);
    cv::Mat planes[2];
    cv::split(spectrum, planes);
    cv::Mat power;
    cv::magnitude(planes[0], planes[1], power);
    sum += power.mul(power);
  }
  // Move the zero frequency to (w/2, h/2).
  cv::Mat shifted(padded, CV_32F);
  const int cx = padded.width / 2, cy = padded.height / 2;
  for (int y = 0; y < padded.height; ++y)
    for (int x = 0; x < padded.width; ++x)
      shifted.at<float>((y + cy) % padded.height, (x + cx) % padded.width) = sum.at<float>(y, x);
  return shifted;
}

float bilinear(const cv::Mat& image, double x, double y) {
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= image.cols || y0 + 1 >= image.rows) return 0.0f;
  const float fx = float(x - x0), fy = float(y - y0);
  const float* r0 = image.ptr<float>(y0);
  const float* r1 = image.ptr<float>(y0 + 1);
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) +
         fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
}

// Energy on the line through the origin at angle `lineDeg` (x right, y down), sampled once per
// frequency bin of the longer side. Frequencies are in cycles per pixel on both axes, so the
// line's angle is a true angle whatever the aspect ratio.
double lineEnergy(const cv::Mat& spectrum, double lineDeg) {
  const double a = lineDeg * M_PI / 180.0;
  const double ux = std::cos(a), uy = std::sin(a);
  const double cx = spectrum.cols / 2, cy = spectrum.rows / 2;
  const double step = 1.0 / std::max(spectrum.cols, spectrum.rows);
  double sum = 0.0;
  for (double r = kMinFrequency; r <= kMaxFrequency; r += step) {
    const double fx = r * ux, fy = r * uy;
    // The spectrum of a real image is symmetric: both halves of the line carry the same energy.
    sum += bilinear(spectrum, cx + fx * spectrum.cols, cy + fy * spectrum.rows);
    sum += bilinear(spectrum, cx - fx * spectrum.cols, cy - fy * spectrum.rows);
  }
  return sum;
}

}  // namespace

RainAngleEstimate estimateRainAngle(const std::vector<cv::Mat>& mattes, double maxAngleDeg) {
  RainAngleEstimate estimate{0.0, 1.0};
  if (mattes.empty() || mattes[0].cols < 8 || mattes[0].rows < 8) return estimate;
  const cv::Mat spectrum = summedPowerSpectrum(mattes);
  double bestDeg = 0.0, bestEnergy = -1.0, total = 0.0;
  int lines = 0;
  // A streak at angle t puts its energy on the spectral line at angle t (x right, y down): the
  // perpendicular of (sin t, -cos t). So the search over lines is the search over streak angles.
  for (double deg = -maxAngleDeg; deg <= maxAngleDeg; deg += kCoarseStepDeg, ++lines) {
    const double e = lineEnergy(spectrum, deg);
    total += e;
    if (e > bestEnergy) bestEnergy = e, bestDeg = deg;
  }
  if (!(total > 0.0)) return estimate;
  for (double deg = bestDeg - kCoarseStepDeg; deg <= bestDeg + kCoarseStepDeg;
       deg += kFineStepDeg) {
    const double e = lineEnergy(spectrum, deg);
    if (e > bestEnergy) bestEnergy = e, bestDeg = deg;
  }
  // The streaks run perpendicular to the spectral line: direction (-sin, cos) of the line's angle.
  const double a = bestDeg * M_PI / 180.0;
  const double sx = -std::sin(a), sy = std::cos(a);
  // frame_stack.h: a streak (sin t, -cos t) has angle t.
  estimate.angleDeg = foldRainAngleDeg(std::atan2(sx, -sy) * 180.0 / M_PI);
  estimate.salience = bestEnergy / (total / lines);
  return estimate;
}

}  // namespace pluvia::derain
