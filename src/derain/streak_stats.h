#pragma once
// Rain streaks in a rain layer, and the statistics `pluvia report realism` compares between real
// rain (a frame minus its clean plate, clean_plate.h) and rendered rain (a render minus its
// plate).
//
// A rain layer is dI = luma(frame) - luma(plate) in 8-bit display codes (0..255 scale, luma =
// 0.2126 R' + 0.7152 G' + 0.0722 B' of the encoded values), with a validity mask (255 valid) and
// the plate's luma for the background terciles.
//
// Detection: an oriented ridge filter (a line detector matched to streaks about 2 px wide), then
// thresholds on dI and on the ridge response, then 8-connected components. Noise, compression and
// residual scene motion pass the same detector; their share is measured by detecting on -dI (the
// false alarms) and subtracted: counts directly, distributions as histograms before quantiles.
//
// Angles are in degrees in (-90, 90] from the image vertical, positive when the streak's upper
// end is right of its lower end (x right, y down; derain/frame_stack.h's convention).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace pluvia::derain {

struct StreakDetectSettings {
  int orientations = 12;         // over 180 degrees
  double sigmaAcrossPx = 1.0;    // of the ridge kernel's second derivative across the streak
  double sigmaAlongPx = 3.0;     // of its Gaussian along the streak
  double thresholdCodes = 10.0;  // dI above which a pixel may be a streak pixel
  double ridgeFraction = 0.5;    // ... when its ridge response also exceeds this x threshold
  int minAreaPx = 3;             // smaller components are not streaks
  double minElongation = 2.5;    // length / width of the streaks that vote for the angle
};

// Fixed bins over [0, binWidth * bins); values beyond fall into the last bin, below into the first.
class Histogram {
 public:
  Histogram(double binWidth, int bins);
  void add(double value, double weight = 1.0);
  // Bin by bin, clamped at 0 (false alarms taken from detections).
  void subtract(const Histogram& other);
  double total() const;
  // Linear within the bin; NaN when empty.
  double quantile(double q) const;

 private:
  double binWidth_;
  std::vector<double> counts_;
};

// The ridge filter: per pixel, the largest response over the orientations and the angle that
// gave it. A bright line about 2 px wide of height h responds about h; flat regions respond 0.
struct RidgeResponse {
  cv::Mat1f response;
  cv::Mat1f angleDeg;
};
RidgeResponse ridgeFilter(const cv::Mat1f& layer, const StreakDetectSettings& settings);

struct Streak {
  int areaPx = 0;
  cv::Point2d centroidPx;  // dI-weighted
  double angleDeg = 0.0;   // of the dI-weighted second moments' principal axis
  double lengthPx = 0.0;   // extent of its pixels along that axis (max - min projection + 1)
  // Pixels at or above half the peak over length: a full width at half maximum. Not area /
  // length, which grows with the streak's height over the threshold (from 2.0 to 2.6 px for a
  // 2 px line of 30 to 60 codes) and so would mix brightness into the width.
  double widthPx = 0.0;
  double peakCodes = 0.0;  // max dI (over ~50 pixels of noise sigma s: about h + 2.5 s)
  double meanCodes = 0.0;  // mean dI
  // Sum of dI over its pixels (codes x px): a drop's light, which blur and the shutter only
  // spread (impliedDropContrastCodes below).
  double energyCodesPx = 0.0;
};

struct StreakDetection {
  cv::Mat1b mask;  // 255 on the pixels of the streaks below
  std::vector<Streak> streaks;
};

// Invalid pixels (valid == 0) count as dI = 0 and are never streak pixels. Throws pluvia::Error
// when the sizes differ.
StreakDetection detectStreaks(const cv::Mat1f& layer, const cv::Mat1b& valid,
                              const StreakDetectSettings& settings = {});

struct StreakStats {
  int frames = 0;
  int64_t validPixels = 0;
  // Raw detections on dI and on -dI (the false alarms subtracted below).
  int64_t streakPixels = 0;
  int64_t falseStreakPixels = 0;
  int64_t streaks = 0;
  int64_t falseStreaks = 0;

  double coverage = 0.0;  // streak pixels per valid pixel, false alarms subtracted, >= 0
  double deltaP50 = 0.0;  // quantiles of dI over streak pixels (codes)
  double deltaP90 = 0.0;
  double deltaP99 = 0.0;
  double streaksPerMpx = 0.0;  // per million valid pixels, false alarms subtracted, >= 0
  double lengthP50Px = 0.0;    // quantiles over streaks
  double widthP50Px = 0.0;
  double peakP90 = 0.0;  // codes
  // Each streak's length over its width, the median weighted by the streak's light (its sum of
  // dI): the shape of the streaks the light is in, what the eye reads as rain (long dashes) or
  // as sleet (round flecks). The medians above count every streak alike, and most are faint.
  double elongationByLightP50 = 0.0;
  double energyP50CodesPx = 0.0;  // of each streak's sum of dI
  // Of each streak's sum of dI over its length squared (codes): impliedDropContrastCodes.
  double energyPerSquareLengthP50 = 0.0;
  // Axial mean of the elongated streaks' angles (weights length x mean dI) and its circular
  // spread (half the circular standard deviation of the doubled angles). NaN without streaks.
  double angleDeg = 0.0;
  double angleSpreadDeg = 0.0;
  // Mean dI of streak pixels over the darkest / brightest third of each frame's valid plate
  // pixels (plate luma); NaN when there are none.
  double deltaDarkThird = 0.0;
  double deltaBrightThird = 0.0;
  // Mean over consecutive frame pairs of the Pearson correlation of the layers' high-pass (layer
  // minus its Gaussian blur of sigma 4 px), over pixels valid in both; NaN without a pair.
  double temporalCorrelation = 0.0;
};

// The luma of the layers' convention (0.2126 R' + 0.7152 G' + 0.0722 B' of the encoded values),
// in the image's own units, of an RGB image or of a BGR one (OpenCV's order).
enum class ChannelOrder { rgb, bgr };
cv::Mat1f lumaOf(const cv::Mat3f& image, ChannelOrder order);

// One frame of a rain layer; all three the same size.
struct RainLayerFrame {
  cv::Mat1f layer;      // dI, codes
  cv::Mat1f plateLuma;  // codes
  cv::Mat1b valid;      // 255 valid
};

class StreakStatsAccumulator {
 public:
  explicit StreakStatsAccumulator(StreakDetectSettings settings = {});
  // `previous`, when given, is the frame before this one in the same sequence (for the temporal
  // correlation). Throws pluvia::Error when the sizes differ.
  void add(const RainLayerFrame& frame, const RainLayerFrame* previous = nullptr);
  StreakStats result() const;

 private:
  // What one sign of the layer (dI, or -dI for the false alarms) contributes.
  struct Side {
    Side();
    int64_t pixels = 0;
    int64_t streaks = 0;
    Histogram delta, length, width, peak, energy, energyPerSquareLength, elongation;
    double angleWeight = 0.0, angleCos = 0.0, angleSin = 0.0;  // of the doubled angles
    double darkSum = 0.0, brightSum = 0.0;
    int64_t darkPixels = 0, brightPixels = 0;
  };
  void addSide(Side& side, const cv::Mat1f& layer, const RainLayerFrame& frame, float darkBelow,
               float brightAbove);

  StreakDetectSettings settings_;
  int frames_ = 0;
  int64_t validPixels_ = 0;
  Side positive_, negative_;
  double correlationSum_ = 0.0;
  int pairs_ = 0;
};

// Garg and Nayar's streak inverted: a drop of image diameter d against a background of B, at a
// radiance of B + C while it lies over a pixel, draws a streak whose dI summed over its pixels is
// C x (the disc's area, pi d^2 / 4) whatever the shutter and the blur (each instant adds its disc
// for its share of the exposure). Its length is L = d + v T f / z with d = D f / z, so
// d = L tau / (tau + T), tau = D / v(D) (dropSecondsPerDiameter(), nearly D's own). So
// C = (sum dI / L^2) (4 / pi) ((tau + T) / tau)^2: the drop's contrast over its background in
// codes, from a streak's energy over its length squared (`energyPerSquareLength`) and the
// shutter. A resolved drop reads about a tenth high (the detector's threshold cuts its streak's
// tapered ends, shortening L more than it loses of the sum); one under a pixel wide reads low.
double impliedDropContrastCodes(double energyPerSquareLength, double shutterSeconds);

// exp(mean |ln r|) over the finite positive ratios: the typical factor by which a set of
// rendered/real ratios is off (2 and 0.5 are both off by 2). NaN when none is usable.
double typicalFactor(const std::vector<double>& ratios);

// rendered / real for the eight numbers that define "typical": coverage, deltaP90, deltaP99,
// streaksPerMpx, lengthP50Px, widthP50Px, peakP90 and elongationByLight (named as here).
std::vector<std::pair<std::string, double>> ratiosToReal(const StreakStats& rendered,
                                                         const StreakStats& real);

}  // namespace pluvia::derain
