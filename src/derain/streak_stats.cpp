// Rain streak detection and the statistics of real against rendered rain (streak_stats.h says
// what is measured).
#include "derain/streak_stats.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_invoke.h>
#include <opencv2/imgproc.hpp>

#include "derain/motion_blur.h"
#include "image/luminance.h"
#include "util/error.h"

namespace pluvia::derain {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kDegPerRad = 180.0 / M_PI;
constexpr double kTemporalSigmaPx = 4.0;

// The reference line the kernels are normalised on: 2 px wide, so a pixel at distance v from
// its axis is covered clamp(1.5 - |v|, 0, 1).
constexpr double kReferenceWidthPx = 2.0;

double lineCoverage(double acrossPx) {
  return std::clamp(0.5 * kReferenceWidthPx + 0.5 - std::abs(acrossPx), 0.0, 1.0);
}

// Unit vector along a streak of the given angle, pointing to its upper end (y down).
cv::Point2d alongAxis(double angleDeg) {
  const double a = angleDeg / kDegPerRad;
  return {std::sin(a), -std::cos(a)};
}

double foldAngleDeg(double angleDeg) {
  while (angleDeg > 90.0) angleDeg -= 180.0;
  while (angleDeg <= -90.0) angleDeg += 180.0;
  return angleDeg;
}

// -G'' across (sigma_across) times G along (sigma_along), made zero-sum (a flat layer responds
// 0) and scaled so that the 2 px reference line of height 1 on the kernel's axis responds 1.
cv::Mat1f ridgeKernel(double angleDeg, const StreakDetectSettings& settings) {
  const double sa = settings.sigmaAcrossPx, sl = settings.sigmaAlongPx;
  const int radius = int(std::ceil(3.0 * std::max(sa, sl)));
  const cv::Point2d along = alongAxis(angleDeg);
  const cv::Point2d across(-along.y, along.x);
  cv::Mat1f ridge(2 * radius + 1, 2 * radius + 1), envelope(ridge.size());
  for (int dy = -radius; dy <= radius; ++dy) {
    for (int dx = -radius; dx <= radius; ++dx) {
      const double u = dx * along.x + dy * along.y, v = dx * across.x + dy * across.y;
      const double gAlong = std::exp(-0.5 * u * u / (sl * sl));
      ridge(dy + radius, dx + radius) =
          float((1.0 - v * v / (sa * sa)) * std::exp(-0.5 * v * v / (sa * sa)) * gAlong);
      // Wider across than the ridge, so removing the sampling's small DC leaves its shape.
      envelope(dy + radius, dx + radius) = float(std::exp(-0.125 * v * v / (sa * sa)) * gAlong);
    }
  }
  ridge -= float(cv::sum(ridge)[0] / cv::sum(envelope)[0]) * envelope;
  double lineResponse = 0.0;
  for (int dy = -radius; dy <= radius; ++dy) {
    for (int dx = -radius; dx <= radius; ++dx) {
      lineResponse += ridge(dy + radius, dx + radius) * lineCoverage(dx * across.x + dy * across.y);
    }
  }
  return ridge / lineResponse;
}

cv::Mat1f maskedLayer(const cv::Mat1f& layer, const cv::Mat1b& valid) {
  cv::Mat1f out = cv::Mat1f::zeros(layer.size());
  layer.copyTo(out, valid);
  cv::patchNaNs(out, 0.0);
  return out;
}

void requireSameSize(const cv::Mat& a, const cv::Mat& b, const char* what) {
  if (a.size() != b.size()) {
    throw Error(std::string("streak statistics: ") + what + " differ in size from the layer");
  }
}

// Per component: dI-weighted moments, then the extent along its axis.
struct ComponentSums {
  int area = 0;
  int halfPeakArea = 0;  // pixels at or above half the peak
  double weight = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0, sxy = 0.0;
  double peak = 0.0;
  double minAlong = std::numeric_limits<double>::infinity();
  double maxAlong = -std::numeric_limits<double>::infinity();
  cv::Point2d axis;
};

// The principal axis of the weighted second moments, in the streak angle convention.
double principalAngleDeg(const ComponentSums& c) {
  const double cx = c.sx / c.weight, cy = c.sy / c.weight;
  const double vxx = c.sxx / c.weight - cx * cx, vyy = c.syy / c.weight - cy * cy;
  const double vxy = c.sxy / c.weight - cx * cy;
  const double theta = 0.5 * std::atan2(2.0 * vxy, vxx - vyy);  // from +x, y down
  return foldAngleDeg(std::atan2(std::cos(theta), -std::sin(theta)) * kDegPerRad);
}

std::vector<ComponentSums> componentSums(const cv::Mat1i& labels, const cv::Mat1f& layer,
                                         int count) {
  std::vector<ComponentSums> sums(count);
  for (int y = 0; y < labels.rows; ++y) {
    for (int x = 0; x < labels.cols; ++x) {
      const int label = labels(y, x);
      if (label == 0) continue;
      ComponentSums& c = sums[label];
      const double w = layer(y, x);
      c.area += 1;
      c.weight += w;
      c.sx += w * x, c.sy += w * y;
      c.sxx += w * x * x, c.syy += w * y * y, c.sxy += w * x * y;
      c.peak = std::max(c.peak, w);
    }
  }
  for (ComponentSums& c : sums) {
    if (c.area > 0) c.axis = alongAxis(principalAngleDeg(c));
  }
  for (int y = 0; y < labels.rows; ++y) {
    for (int x = 0; x < labels.cols; ++x) {
      if (labels(y, x) == 0) continue;
      ComponentSums& c = sums[labels(y, x)];
      const double along = x * c.axis.x + y * c.axis.y;
      c.minAlong = std::min(c.minAlong, along);
      c.maxAlong = std::max(c.maxAlong, along);
      if (layer(y, x) >= 0.5 * c.peak) c.halfPeakArea += 1;
    }
  }
  return sums;
}

Streak streakOf(const ComponentSums& c) {
  Streak s;
  s.areaPx = c.area;
  s.centroidPx = {c.sx / c.weight, c.sy / c.weight};
  s.angleDeg = principalAngleDeg(c);
  s.lengthPx = c.maxAlong - c.minAlong + 1.0;
  s.widthPx = c.halfPeakArea / s.lengthPx;
  s.peakCodes = c.peak;
  s.meanCodes = c.weight / c.area;
  s.energyCodesPx = c.weight;
  return s;
}

// Layer minus its blur of sigma 4 px, the blur normalised over `valid` so invalid pixels do not
// leak in.
cv::Mat1f highPass(const cv::Mat1f& layer, const cv::Mat1b& valid) {
  cv::Mat1f weight;
  valid.convertTo(weight, CV_32F, 1.0 / 255.0);
  cv::Mat1f values = maskedLayer(layer, valid), blurredValues, blurredWeight;
  cv::GaussianBlur(values, blurredValues, {0, 0}, kTemporalSigmaPx);
  cv::GaussianBlur(weight, blurredWeight, {0, 0}, kTemporalSigmaPx);
  return values - blurredValues / cv::max(blurredWeight, 1e-6f);
}

// NaN when either side is constant over the mask.
double pearson(const cv::Mat1f& a, const cv::Mat1f& b, const cv::Mat1b& mask) {
  double n = 0, sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  for (int y = 0; y < a.rows; ++y) {
    for (int x = 0; x < a.cols; ++x) {
      if (!mask(y, x)) continue;
      const double va = a(y, x), vb = b(y, x);
      n += 1, sa += va, sb += vb, saa += va * va, sbb += vb * vb, sab += va * vb;
    }
  }
  const double cov = sab - sa * sb / n, varA = saa - sa * sa / n, varB = sbb - sb * sb / n;
  if (!(varA > 0.0 && varB > 0.0)) return kNaN;
  return cov / std::sqrt(varA * varB);
}

// The values at 1/3 and 2/3 of the sorted plate luma over valid pixels.
std::pair<float, float> terciles(const cv::Mat1f& plateLuma, const cv::Mat1b& valid) {
  std::vector<float> values;
  for (int y = 0; y < plateLuma.rows; ++y) {
    for (int x = 0; x < plateLuma.cols; ++x) {
      if (valid(y, x)) values.push_back(plateLuma(y, x));
    }
  }
  if (values.empty()) return {0.0f, 0.0f};
  const auto at = [&](size_t i) {
    std::nth_element(values.begin(), values.begin() + i, values.end());
    return values[i];
  };
  const float dark = at(values.size() / 3);
  return {dark, at(2 * values.size() / 3)};
}

// Histograms of dI and peaks: 0.5-code bins to 256; of lengths and widths: 0.25 px to 512.
Histogram codesHistogram() {
  return Histogram(0.5, 512);
}
Histogram pixelsHistogram() {
  return Histogram(0.25, 2048);
}
// Of energies (codes x px): 2 to 16384; of energies over length squared (codes): 0.02 to 164.
Histogram energyHistogram() {
  return Histogram(2.0, 8192);
}
Histogram energyPerSquareLengthHistogram() {
  return Histogram(0.02, 8192);
}

double quantileOfDifference(Histogram positive, const Histogram& negative, double q) {
  positive.subtract(negative);
  return positive.quantile(q);
}

}  // namespace

Histogram::Histogram(double binWidth, int bins) : binWidth_(binWidth), counts_(bins, 0.0) {}

void Histogram::add(double value, double weight) {
  const int last = int(counts_.size()) - 1;
  const int bin = int(std::clamp(std::floor(value / binWidth_), 0.0, double(last)));
  counts_[bin] += weight;
}

void Histogram::subtract(const Histogram& other) {
  for (size_t i = 0; i < counts_.size(); ++i) {
    counts_[i] = std::max(0.0, counts_[i] - other.counts_.at(i));
  }
}

double Histogram::total() const {
  double sum = 0.0;
  for (double c : counts_) sum += c;
  return sum;
}

double Histogram::quantile(double q) const {
  const double target = std::clamp(q, 0.0, 1.0) * total();
  if (!(total() > 0.0)) return kNaN;
  double below = 0.0;
  for (size_t i = 0; i < counts_.size(); ++i) {
    if (counts_[i] > 0.0 && below + counts_[i] >= target) {
      return (double(i) + (target - below) / counts_[i]) * binWidth_;
    }
    below += counts_[i];
  }
  return double(counts_.size()) * binWidth_;
}

RidgeResponse ridgeFilter(const cv::Mat1f& layer, const StreakDetectSettings& settings) {
  RidgeResponse out{cv::Mat1f(layer.size(), -std::numeric_limits<float>::infinity()),
                    cv::Mat1f::zeros(layer.size())};
  cv::Mat1f filtered;
  for (int i = 0; i < settings.orientations; ++i) {
    const double angleDeg = foldAngleDeg(-90.0 + 180.0 * (i + 1) / settings.orientations);
    cv::filter2D(layer, filtered, CV_32F, ridgeKernel(angleDeg, settings));
    const cv::Mat1b better = filtered > out.response;
    filtered.copyTo(out.response, better);
    out.angleDeg.setTo(float(angleDeg), better);
  }
  return out;
}

StreakDetection detectStreaks(const cv::Mat1f& layer, const cv::Mat1b& valid,
                              const StreakDetectSettings& settings) {
  requireSameSize(valid, layer, "validity mask");
  const cv::Mat1f values = maskedLayer(layer, valid);
  const RidgeResponse ridge = ridgeFilter(values, settings);
  const float threshold = float(settings.thresholdCodes);
  const cv::Mat1b candidates =
      (values > threshold) & (ridge.response > float(settings.ridgeFraction) * threshold);
  cv::Mat1i labels, stats;
  cv::Mat centroids;
  const int count = cv::connectedComponentsWithStats(candidates, labels, stats, centroids, 8);
  for (int y = 0; y < labels.rows; ++y) {
    for (int x = 0; x < labels.cols; ++x) {
      int& label = labels(y, x);
      if (label > 0 && stats(label, cv::CC_STAT_AREA) < settings.minAreaPx) label = 0;
    }
  }
  StreakDetection out{labels > 0, {}};
  for (const ComponentSums& c : componentSums(labels, values, count)) {
    if (c.area > 0) out.streaks.push_back(streakOf(c));
  }
  return out;
}

StreakStatsAccumulator::Side::Side()
    : delta(codesHistogram()),
      length(pixelsHistogram()),
      width(pixelsHistogram()),
      peak(codesHistogram()),
      energy(energyHistogram()),
      energyPerSquareLength(energyPerSquareLengthHistogram()),
      elongation(pixelsHistogram()) {}

StreakStatsAccumulator::StreakStatsAccumulator(StreakDetectSettings settings)
    : settings_(settings) {}

void StreakStatsAccumulator::add(const RainLayerFrame& frame, const RainLayerFrame* previous) {
  requireSameSize(frame.valid, frame.layer, "validity mask");
  requireSameSize(frame.plateLuma, frame.layer, "plate luma");
  const auto [darkBelow, brightAbove] = terciles(frame.plateLuma, frame.valid);
  // The two signs in parallel: each side has its own sums.
  const cv::Mat1f negated = -frame.layer;
  tbb::parallel_invoke([&] { addSide(positive_, frame.layer, frame, darkBelow, brightAbove); },
                       [&] { addSide(negative_, negated, frame, darkBelow, brightAbove); });
  frames_ += 1;
  validPixels_ += cv::countNonZero(frame.valid);
  if (previous) {
    requireSameSize(previous->layer, frame.layer, "previous frame's layer");
    requireSameSize(previous->valid, frame.layer, "previous frame's validity mask");
    const cv::Mat1b both = frame.valid & previous->valid;
    const double r = pearson(highPass(previous->layer, both), highPass(frame.layer, both), both);
    if (std::isfinite(r)) correlationSum_ += r, pairs_ += 1;
  }
}

void StreakStatsAccumulator::addSide(Side& side, const cv::Mat1f& layer,
                                     const RainLayerFrame& frame, float darkBelow,
                                     float brightAbove) {
  const StreakDetection detection = detectStreaks(layer, frame.valid, settings_);
  for (int y = 0; y < layer.rows; ++y) {
    for (int x = 0; x < layer.cols; ++x) {
      if (!detection.mask(y, x)) continue;
      const double delta = layer(y, x);
      const float plate = frame.plateLuma(y, x);
      side.pixels += 1;
      side.delta.add(delta);
      if (plate < darkBelow) side.darkSum += delta, side.darkPixels += 1;
      if (plate >= brightAbove) side.brightSum += delta, side.brightPixels += 1;
    }
  }
  for (const Streak& s : detection.streaks) {
    side.streaks += 1;
    side.length.add(s.lengthPx);
    side.width.add(s.widthPx);
    side.peak.add(s.peakCodes);
    side.energy.add(s.energyCodesPx);
    side.energyPerSquareLength.add(s.energyCodesPx / (s.lengthPx * s.lengthPx));
    if (s.widthPx > 0.0) side.elongation.add(s.lengthPx / s.widthPx, s.energyCodesPx);
    if (s.lengthPx < settings_.minElongation * s.widthPx) continue;
    const double w = s.lengthPx * s.meanCodes, doubled = 2.0 * s.angleDeg / kDegPerRad;
    side.angleWeight += w;
    side.angleCos += w * std::cos(doubled);
    side.angleSin += w * std::sin(doubled);
  }
}

StreakStats StreakStatsAccumulator::result() const {
  const Side& p = positive_;
  const Side& n = negative_;
  StreakStats s;
  s.frames = frames_;
  s.validPixels = validPixels_;
  s.streakPixels = p.pixels;
  s.falseStreakPixels = n.pixels;
  s.streaks = p.streaks;
  s.falseStreaks = n.streaks;
  const double valid = validPixels_ > 0 ? double(validPixels_) : kNaN;
  s.coverage = std::max<int64_t>(0, p.pixels - n.pixels) / valid;
  s.streaksPerMpx = std::max<int64_t>(0, p.streaks - n.streaks) / valid * 1e6;
  s.deltaP50 = quantileOfDifference(p.delta, n.delta, 0.5);
  s.deltaP90 = quantileOfDifference(p.delta, n.delta, 0.9);
  s.deltaP99 = quantileOfDifference(p.delta, n.delta, 0.99);
  s.lengthP50Px = quantileOfDifference(p.length, n.length, 0.5);
  s.widthP50Px = quantileOfDifference(p.width, n.width, 0.5);
  s.peakP90 = quantileOfDifference(p.peak, n.peak, 0.9);
  s.elongationByLightP50 = quantileOfDifference(p.elongation, n.elongation, 0.5);
  s.energyP50CodesPx = quantileOfDifference(p.energy, n.energy, 0.5);
  s.energyPerSquareLengthP50 =
      quantileOfDifference(p.energyPerSquareLength, n.energyPerSquareLength, 0.5);

  // The false alarms' votes are subtracted like every other count: their doubled-angle vectors
  // from the sums, their weights from the total.
  const double weight = p.angleWeight - n.angleWeight;
  const double c = p.angleCos - n.angleCos, sn = p.angleSin - n.angleSin;
  if (weight > 0.0) {
    const double resultant = std::clamp(std::hypot(c, sn) / weight, 0.0, 1.0);
    s.angleDeg = foldAngleDeg(0.5 * std::atan2(sn, c) * kDegPerRad);
    s.angleSpreadDeg = 0.5 * std::sqrt(-2.0 * std::log(resultant)) * kDegPerRad;
  } else {
    s.angleDeg = s.angleSpreadDeg = kNaN;
  }
  const auto meanOfDifference = [](double sumP, int64_t countP, double sumN, int64_t countN) {
    return countP > countN ? (sumP - sumN) / double(countP - countN) : kNaN;
  };
  s.deltaDarkThird = meanOfDifference(p.darkSum, p.darkPixels, n.darkSum, n.darkPixels);
  s.deltaBrightThird = meanOfDifference(p.brightSum, p.brightPixels, n.brightSum, n.brightPixels);
  s.temporalCorrelation = pairs_ > 0 ? correlationSum_ / pairs_ : kNaN;
  return s;
}

double impliedDropContrastCodes(double energyPerSquareLength, double shutterSeconds) {
  const double tau = dropSecondsPerDiameter();
  const double lengthOverDiameter = (tau + std::max(shutterSeconds, 0.0)) / tau;
  return energyPerSquareLength * (4.0 / M_PI) * lengthOverDiameter * lengthOverDiameter;
}

double typicalFactor(const std::vector<double>& ratios) {
  double sum = 0.0;
  int count = 0;
  for (double r : ratios) {
    if (std::isfinite(r) && r > 0.0) sum += std::abs(std::log(r)), count += 1;
  }
  return count > 0 ? std::exp(sum / count) : kNaN;
}

std::vector<std::pair<std::string, double>> ratiosToReal(const StreakStats& rendered,
                                                         const StreakStats& real) {
  return {{"coverage", rendered.coverage / real.coverage},
          {"deltaP90", rendered.deltaP90 / real.deltaP90},
          {"deltaP99", rendered.deltaP99 / real.deltaP99},
          {"streaksPerMpx", rendered.streaksPerMpx / real.streaksPerMpx},
          {"lengthP50Px", rendered.lengthP50Px / real.lengthP50Px},
          {"widthP50Px", rendered.widthP50Px / real.widthP50Px},
          {"peakP90", rendered.peakP90 / real.peakP90},
          {"elongationByLight", rendered.elongationByLightP50 / real.elongationByLightP50}};
}

cv::Mat1f lumaOf(const cv::Mat3f& image, ChannelOrder order) {
  const float r = float(kRec709Red), g = float(kRec709Green), b = float(kRec709Blue);
  cv::Mat1f y(image.size());
  cv::transform(image, y, order == ChannelOrder::rgb ? cv::Matx13f(r, g, b) : cv::Matx13f(b, g, r));
  return y;
}

}  // namespace pluvia::derain
