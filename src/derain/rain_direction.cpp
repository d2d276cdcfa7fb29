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
// The spectrum is taken over tiles: rain covers the frame, while what else the mattes hold
// (misregistered edges, a pillar's parallax, splashes) is local, so tiles that see rain agree on
// a line where the one spectrum of the whole frame can be won by a few strong scene edges.
constexpr int kTilePx = 96;
// Tiles whose lines lie within this of one another vote together.
constexpr double kAgreementDeg = 2.5;

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

// One tile's best line in [-maxAngleDeg, maxAngleDeg] (coarse, then fine), its salience (energy
// on it over the mean over the coarse lines) and that mean.
struct TileLine {
  double lineDeg = 0.0, salience = 1.0, meanEnergy = 0.0;
  bool atRangeEnd = false;  // the best line lies at the searched range's end: beyond it, really
};

TileLine bestLine(const cv::Mat& spectrum, double maxAngleDeg) {
  TileLine out;
  double bestEnergy = -1.0, total = 0.0;
  int lines = 0;
  for (double deg = -maxAngleDeg; deg <= maxAngleDeg; deg += kCoarseStepDeg, ++lines) {
    const double e = lineEnergy(spectrum, deg);
    total += e;
    if (e > bestEnergy) bestEnergy = e, out.lineDeg = deg;
  }
  if (!(total > 0.0)) return out;
  out.meanEnergy = total / lines;
  out.atRangeEnd = maxAngleDeg < 90.0 && std::abs(out.lineDeg) > maxAngleDeg - 1.0;
  for (double deg = out.lineDeg - kCoarseStepDeg; deg <= out.lineDeg + kCoarseStepDeg;
       deg += kFineStepDeg) {
    const double e = lineEnergy(spectrum, deg);
    if (e > bestEnergy) bestEnergy = e, out.lineDeg = deg;
  }
  out.salience = bestEnergy / out.meanEnergy;
  return out;
}

// a - b folded into (-90, 90]: lines at a and b differ by this much.
double lineDifferenceDeg(double a, double b) {
  return foldRainAngleDeg(a - b);
}

}  // namespace

RainAngleEstimate estimateRainAngle(const std::vector<cv::Mat>& mattes, double maxAngleDeg) {
  RainAngleEstimate estimate;
  if (mattes.empty() || mattes[0].cols < 8 || mattes[0].rows < 8) return estimate;
  const cv::Size size = mattes[0].size();
  // Tiles of kTilePx (the whole side when shorter), overlapping by half.
  const int tileW = std::min(kTilePx, size.width), tileH = std::min(kTilePx, size.height);
  auto starts = [](int length, int tile) {
    std::vector<int> out;
    for (int s = 0; s + tile <= length; s += std::max(1, tile / 2)) out.push_back(s);
    if (out.back() + tile < length) out.push_back(length - tile);
    return out;
  };
  struct Tile {
    cv::Mat spectrum;
    TileLine line;
  };
  std::vector<Tile> tiles;
  for (int y : starts(size.height, tileH))
    for (int x : starts(size.width, tileW)) {
      std::vector<cv::Mat> views;
      for (const cv::Mat& m : mattes) views.push_back(m(cv::Rect(x, y, tileW, tileH)));
      Tile t;
      t.spectrum = summedPowerSpectrum(views);
      t.line = bestLine(t.spectrum, maxAngleDeg);
      if (t.line.meanEnergy > 0.0) tiles.push_back(std::move(t));
    }
  if (tiles.empty()) return estimate;

  // Each tile votes for its best line with weight salience - 1; a tile whose best line lies at
  // the range's end votes for a line outside it (a scene edge) and not at all. The tile line
  // with the most vote within kAgreementDeg of it wins; the votes that near it give the angle
  // (their weighted mean).
  auto weight = [](const Tile& t) { return t.line.atRangeEnd ? 0.0 : t.line.salience - 1.0; };
  double total = 0.0, bestSupport = -1.0, peakDeg = 0.0;
  for (const Tile& t : tiles) total += weight(t);
  if (!(total > 0.0)) return estimate;
  for (const Tile& candidate : tiles) {
    double support = 0.0;
    for (const Tile& t : tiles)
      if (std::abs(lineDifferenceDeg(t.line.lineDeg, candidate.line.lineDeg)) <= kAgreementDeg)
        support += weight(t);
    if (support > bestSupport) bestSupport = support, peakDeg = candidate.line.lineDeg;
  }
  double offsetSum = 0.0, agreeing = 0.0;
  for (const Tile& t : tiles) {
    const double offset = lineDifferenceDeg(t.line.lineDeg, peakDeg);
    if (std::abs(offset) <= kAgreementDeg) offsetSum += weight(t) * offset, agreeing += weight(t);
  }
  const double lineDeg = peakDeg + (agreeing > 0.0 ? offsetSum / agreeing : 0.0);
  // Its salience over all tiles: the geometric mean of each tile's energy on that line over
  // its mean energy (a tile of other structure or of noise pulls it towards or below 1).
  double logSum = 0.0;
  for (const Tile& t : tiles)
    logSum += std::log(std::max(lineEnergy(t.spectrum, lineDeg), 1e-30) / t.line.meanEnergy);
  // The streaks run perpendicular to the spectral line: direction (-sin, cos) of the line's angle.
  const double a = lineDeg * M_PI / 180.0;
  const double sx = -std::sin(a), sy = std::cos(a);
  // frame_stack.h: a streak (sin t, -cos t) has angle t.
  estimate.angleDeg = foldRainAngleDeg(std::atan2(sx, -sy) * 180.0 / M_PI);
  estimate.salience = std::exp(logSum / double(tiles.size()));
  estimate.agreement = agreeing / total;
  return estimate;
}

}  // namespace pluvia::derain
