// lab/streak_stats.h on synthetic rain layers of known truth: streaks of known count, length,
// width, angle and brightness over seeded sensor noise are recovered; pure noise reads no rain
// once the false alarms (the detector on -dI) are subtracted; streaks spread evenly over a plate
// ramping left to right read the same dI in its dark and bright thirds; a repeated layer
// correlates in time and independent ones do not; and the typical factor of {2, 0.5} is 2.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "derain/motion_blur.h"
#include "derain/streak_stats.h"
#include "util/error.h"

using namespace pluvia;
using namespace pluvia::derain;

namespace {

constexpr int kWidth = 640, kHeight = 360;
constexpr double kNoiseCodes = 2.0;
constexpr double kWidthPx = 2.0;

cv::Mat1f noise(uint64_t seed) {
  cv::Mat1f out(kHeight, kWidth);
  cv::RNG rng(seed);
  rng.fill(out, cv::RNG::NORMAL, 0.0, kNoiseCodes);
  return out;
}

// Adds a streak of height h, 2 px wide (box profile, each pixel weighted by its coverage) and
// `lengthPx` long, centred at `centre` at `angleDeg` (streak_stats.h convention).
void drawStreak(cv::Mat1f& layer, cv::Point2d centre, double lengthPx, double angleDeg, double h) {
  const double a = angleDeg * M_PI / 180.0;
  const cv::Point2d along(std::sin(a), -std::cos(a)), across(std::cos(a), std::sin(a));
  const int reach = int(lengthPx / 2 + 3);
  for (int y = int(centre.y) - reach; y <= int(centre.y) + reach; ++y) {
    for (int x = int(centre.x) - reach; x <= int(centre.x) + reach; ++x) {
      const cv::Point2d d(x - centre.x, y - centre.y);
      const double u = d.dot(along), v = d.dot(across);
      const double coverAcross = std::clamp(kWidthPx / 2 + 0.5 - std::abs(v), 0.0, 1.0);
      const double coverAlong = std::clamp(lengthPx / 2 + 0.5 - std::abs(u), 0.0, 1.0);
      layer(y, x) += float(h * coverAcross * coverAlong);
    }
  }
}

// Streak centres on an 8 x 5 grid, jittered by a seeded +-8 px: 40 streaks that never touch.
std::vector<cv::Point2d> gridCentres(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(-8.0, 8.0);
  std::vector<cv::Point2d> out;
  for (int row = 0; row < 5; ++row) {
    for (int col = 0; col < 8; ++col) {
      out.push_back({80.0 * col + 40.0 + jitter(rng), 72.0 * row + 36.0 + jitter(rng)});
    }
  }
  return out;
}

cv::Mat1b allValid() {
  return cv::Mat1b(kHeight, kWidth, uchar(255));
}

// A plate whose luma ramps from 20 codes on the left to 220 on the right.
cv::Mat1f rampPlate() {
  cv::Mat1f out(kHeight, kWidth);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) out(y, x) = float(20.0 + 200.0 * x / (kWidth - 1));
  }
  return out;
}

struct Case {
  double lengthPx;
  double angleDeg;
  double heightCodes;
};

StreakStats statsOf(const Case& c, uint64_t seed, int frames = 1) {
  StreakStatsAccumulator accumulator;
  for (int f = 0; f < frames; ++f) {
    cv::Mat1f layer = noise(seed + f);
    for (cv::Point2d centre : gridCentres(seed + 100 + f)) {
      drawStreak(layer, centre, c.lengthPx, c.angleDeg, c.heightCodes);
    }
    accumulator.add({layer, rampPlate(), allValid()});
  }
  return accumulator.result();
}

class KnownStreaks : public ::testing::TestWithParam<Case> {};

TEST_P(KnownStreaks, AreRecovered) {
  const Case c = GetParam();
  const StreakStats stats = statsOf(c, 7, 2);
  const double truePerMpx = 40.0 / (kWidth * kHeight) * 1e6;
  EXPECT_NEAR(stats.streaksPerMpx, truePerMpx, 0.10 * truePerMpx);
  EXPECT_NEAR(stats.lengthP50Px, c.lengthPx, 0.15 * c.lengthPx);
  EXPECT_NEAR(stats.widthP50Px, kWidthPx, 0.30 * kWidthPx);
  EXPECT_NEAR(stats.angleDeg, c.angleDeg, 2.0);
  EXPECT_LT(stats.angleSpreadDeg, 3.0);
  // The max over a streak's pixels reads its height plus about 2.5 sigma of noise.
  EXPECT_NEAR(stats.peakP90, c.heightCodes, 0.15 * c.heightCodes);
  // The streaks' dI: at most their height plus noise, and mostly near it.
  EXPECT_LT(stats.deltaP99, c.heightCodes + 4.0 * kNoiseCodes);
  EXPECT_GT(stats.deltaP90, 0.8 * c.heightCodes);
  const double trueCoverage = 40.0 * c.lengthPx * kWidthPx / (kWidth * kHeight);
  EXPECT_GT(stats.coverage, 0.8 * trueCoverage);
  EXPECT_LT(stats.coverage, 1.6 * trueCoverage);
  EXPECT_EQ(stats.frames, 2);
  EXPECT_EQ(stats.validPixels, 2 * kWidth * kHeight);
  std::printf(
      "L %.0f angle %.0f h %.0f: count/true %.3f length %.2f width %.2f angle %.2f "
      "(spread %.2f) peak %.2f coverage/true %.2f dP50 %.1f dP90 %.1f dP99 %.1f "
      "false %lld/%lld\n",
      c.lengthPx, c.angleDeg, c.heightCodes, stats.streaksPerMpx / truePerMpx, stats.lengthP50Px,
      stats.widthP50Px, stats.angleDeg, stats.angleSpreadDeg, stats.peakP90,
      stats.coverage / trueCoverage, stats.deltaP50, stats.deltaP90, stats.deltaP99,
      (long long)stats.falseStreaks, (long long)stats.streaks);
}

INSTANTIATE_TEST_SUITE_P(Lines, KnownStreaks,
                         ::testing::Values(Case{30.0, 15.0, 40.0}, Case{20.0, -30.0, 60.0},
                                           Case{40.0, 0.0, 40.0}, Case{25.0, 75.0, 50.0},
                                           Case{30.0, 90.0, 40.0}, Case{16.0, -60.0, 40.0}));

// Where the light is: 10 long bright streaks (24 px by 2, 60 codes: each about 2900 codes px)
// among 30 faint short ones (4 px by 2, 25 codes: about 200). Counted alike, the streaks' median
// length is a short one's; weighted by their light, the median shape is the long ones' 24 / 2.
TEST(StreakStats, TheElongationByLightIsTheShapeOfTheStreaksTheLightIsIn) {
  cv::Mat1f layer = noise(5);
  const std::vector<cv::Point2d> centres = gridCentres(11);
  for (size_t i = 0; i < centres.size(); ++i) {
    if (i % 4 == 0)
      drawStreak(layer, centres[i], 24.0, 0.0, 60.0);
    else
      drawStreak(layer, centres[i], 4.0, 0.0, 25.0);
  }
  StreakStatsAccumulator accumulator;
  accumulator.add({layer, rampPlate(), allValid()});
  const StreakStats stats = accumulator.result();
  EXPECT_LT(stats.lengthP50Px, 8.0);
  EXPECT_NEAR(stats.elongationByLightP50, 24.0 / kWidthPx, 0.2 * 24.0 / kWidthPx);
}

TEST(StreakStats, DetectsEachStreakOnceWithItsAngle) {
  cv::Mat1f layer = noise(3);
  drawStreak(layer, {200.5, 150.0}, 30.0, 20.0, 50.0);
  drawStreak(layer, {450.0, 200.0}, 30.0, -20.0, 50.0);
  const StreakDetection detection = detectStreaks(layer, allValid());
  ASSERT_EQ(detection.streaks.size(), 2u);
  const Streak& left =
      detection.streaks[0].centroidPx.x < 300 ? detection.streaks[0] : detection.streaks[1];
  const Streak& right =
      &left == &detection.streaks[0] ? detection.streaks[1] : detection.streaks[0];
  EXPECT_NEAR(left.angleDeg, 20.0, 2.0);
  EXPECT_NEAR(right.angleDeg, -20.0, 2.0);
  EXPECT_NEAR(left.centroidPx.x, 200.5, 0.5);
  EXPECT_NEAR(left.centroidPx.y, 150.0, 0.5);
}

TEST(StreakStats, RidgeRespondsWithTheLineHeight) {
  cv::Mat1f layer = cv::Mat1f::zeros(kHeight, kWidth);
  drawStreak(layer, {320.0, 180.0}, 200.0, 10.0, 40.0);
  const RidgeResponse ridge = ridgeFilter(layer, {});
  EXPECT_NEAR(ridge.response(180, 320), 40.0, 4.0);
  EXPECT_NEAR(ridge.angleDeg(180, 320), 15.0, 7.5);  // the nearest of the 12 orientations
  // Flat regions respond zero.
  const cv::Mat1f flat(64, 64, 100.0f);
  EXPECT_NEAR(ridgeFilter(flat, {}).response(32, 32), 0.0, 1e-3);
}

TEST(StreakStats, PureNoiseReadsNoRain) {
  StreakStatsAccumulator accumulator;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    cv::Mat1f layer = noise(seed);
    // Heavier-tailed noise too: a few isolated blocky compression errors of either sign.
    cv::RNG rng(seed);
    for (int i = 0; i < 200; ++i) {
      const int x = rng.uniform(0, kWidth - 3), y = rng.uniform(0, kHeight - 3);
      layer(cv::Rect(x, y, 3, 2)) += float(i % 2 ? 14.0 : -14.0);
    }
    accumulator.add({layer, rampPlate(), allValid()});
  }
  const StreakStats stats = accumulator.result();
  EXPECT_GT(stats.falseStreaks, 0);  // the detector does fire on noise...
  EXPECT_LT(stats.coverage, 2e-4);   // ... and the subtraction removes it
  EXPECT_LT(stats.streaksPerMpx, 60.0);
  std::printf("noise: streaks %lld false %lld -> %.1f per Mpx, coverage %.2e\n",
              (long long)stats.streaks, (long long)stats.falseStreaks, stats.streaksPerMpx,
              stats.coverage);
}

TEST(StreakStats, InvalidPixelsAreNeverStreaks) {
  cv::Mat1f layer = noise(5);
  drawStreak(layer, {320.0, 180.0}, 30.0, 0.0, 50.0);
  cv::Mat1b valid = allValid();
  valid(cv::Rect(300, 100, 40, 160)).setTo(0);
  EXPECT_TRUE(detectStreaks(layer, valid).streaks.empty());
  EXPECT_THROW(detectStreaks(layer, cv::Mat1b(10, 10, uchar(255))), Error);
}

TEST(StreakStats, TercilesReadTheSameForEvenlySpreadStreaks) {
  const StreakStats stats = statsOf({30.0, 10.0, 40.0}, 11, 3);
  ASSERT_TRUE(std::isfinite(stats.deltaDarkThird));
  ASSERT_TRUE(std::isfinite(stats.deltaBrightThird));
  EXPECT_NEAR(stats.deltaDarkThird, stats.deltaBrightThird, 2.0);
  EXPECT_GT(stats.deltaDarkThird, 20.0);
  std::printf("terciles: dark %.2f bright %.2f\n", stats.deltaDarkThird, stats.deltaBrightThird);
}

TEST(StreakStats, TercilesFollowTheBackground) {
  // Rain brighter over the dark plate (left) than over the bright one (right).
  StreakStatsAccumulator accumulator;
  cv::Mat1f layer = noise(9);
  for (cv::Point2d centre : gridCentres(13)) {
    drawStreak(layer, centre, 30.0, 0.0, centre.x < kWidth / 2 ? 60.0 : 30.0);
  }
  accumulator.add({layer, rampPlate(), allValid()});
  const StreakStats stats = accumulator.result();
  EXPECT_GT(stats.deltaDarkThird, stats.deltaBrightThird + 15.0);
}

TEST(StreakStats, TemporalCorrelation) {
  cv::Mat1f layer = noise(21);
  for (cv::Point2d centre : gridCentres(22)) drawStreak(layer, centre, 30.0, 10.0, 40.0);
  const RainLayerFrame frame{layer, rampPlate(), allValid()};

  StreakStatsAccumulator repeated;
  repeated.add(frame);
  EXPECT_TRUE(std::isnan(repeated.result().temporalCorrelation));  // one frame: no pair
  repeated.add(frame, &frame);
  EXPECT_NEAR(repeated.result().temporalCorrelation, 1.0, 1e-6);

  StreakStatsAccumulator independent;
  RainLayerFrame previous = frame;
  for (uint64_t seed = 30; seed < 33; ++seed) {
    cv::Mat1f next = noise(seed);
    for (cv::Point2d centre : gridCentres(seed + 50)) drawStreak(next, centre, 30.0, 10.0, 40.0);
    const RainLayerFrame current{next, rampPlate(), allValid()};
    independent.add(current, &previous);
    previous = current;
  }
  EXPECT_NEAR(independent.result().temporalCorrelation, 0.0, 0.05);
}

TEST(StreakStats, HistogramQuantilesAndSubtraction) {
  Histogram h(0.5, 512);
  for (int i = 0; i < 100; ++i) h.add(10.25);
  for (int i = 0; i < 100; ++i) h.add(50.25);
  EXPECT_NEAR(h.quantile(0.25), 10.25, 0.5);
  EXPECT_NEAR(h.quantile(0.75), 50.25, 0.5);
  Histogram falseAlarms(0.5, 512);
  for (int i = 0; i < 150; ++i) falseAlarms.add(10.25);
  h.subtract(falseAlarms);
  EXPECT_DOUBLE_EQ(h.total(), 100.0);  // clamped at zero, not -50
  EXPECT_NEAR(h.quantile(0.1), 50.25, 0.5);
  EXPECT_TRUE(std::isnan(Histogram(0.5, 8).quantile(0.5)));
}

TEST(StreakStats, TypicalFactor) {
  EXPECT_DOUBLE_EQ(typicalFactor({2.0, 0.5}), 2.0);
  EXPECT_NEAR(typicalFactor({1.0, 4.0, -1.0, std::nan("")}), 2.0, 1e-12);
  EXPECT_TRUE(std::isnan(typicalFactor({})));

  StreakStats real, rendered;
  real.coverage = 0.01, rendered.coverage = 0.02;
  real.deltaP90 = rendered.deltaP90 = 30.0;
  real.deltaP99 = rendered.deltaP99 = 50.0;
  real.streaksPerMpx = 100.0, rendered.streaksPerMpx = 50.0;
  real.lengthP50Px = rendered.lengthP50Px = 20.0;
  real.widthP50Px = rendered.widthP50Px = 2.0;
  real.peakP90 = rendered.peakP90 = 60.0;
  real.elongationByLightP50 = rendered.elongationByLightP50 = 6.0;
  const auto ratios = ratiosToReal(rendered, real);
  ASSERT_EQ(ratios.size(), 8u);
  EXPECT_EQ(ratios[0].first, "coverage");
  EXPECT_DOUBLE_EQ(ratios[0].second, 2.0);
  EXPECT_DOUBLE_EQ(ratios[3].second, 0.5);
  std::vector<double> values;
  for (const auto& [name, value] : ratios) values.push_back(value);
  EXPECT_NEAR(typicalFactor(values), std::exp(2.0 * std::log(2.0) / 8.0), 1e-12);
}

}  // namespace

// A drop of 6 px brighter than its background by 150 codes, filmed over 4 times the time it
// takes to fall its diameter: its disc swept 24 px (400 instants, each pixel's share of the
// disc from 4 x 4 samples), over noise. Its streak's light inverts back into its contrast.
TEST(StreakStats, AStreakInvertsIntoItsDropsContrast) {
  constexpr double kDiameterPx = 6.0, kContrastCodes = 150.0, kShutterOverTau = 4.0;
  constexpr int kInstants = 400;
  cv::Mat1f layer = noise(11);
  const cv::Point2d start(320.0, 160.0);
  const double pathPx = kShutterOverTau * kDiameterPx;
  for (int y = 150; y < 200; ++y)
    for (int x = 310; x < 330; ++x) {
      double covered = 0.0;
      for (int i = 0; i < kInstants; ++i) {
        const double cy = start.y + pathPx * (i + 0.5) / kInstants;
        for (int sy = 0; sy < 4; ++sy)
          for (int sx = 0; sx < 4; ++sx) {
            const double dx = x - 0.375 + 0.25 * sx - start.x, dy = y - 0.375 + 0.25 * sy - cy;
            covered += (dx * dx + dy * dy <= 0.25 * kDiameterPx * kDiameterPx) ? 1.0 : 0.0;
          }
      }
      layer(y, x) += float(kContrastCodes * covered / (16.0 * kInstants));
    }
  const StreakDetection detection = detectStreaks(layer, allValid());
  ASSERT_EQ(detection.streaks.size(), 1u);
  const Streak& s = detection.streaks[0];
  // Its ends taper over a diameter (less of the disc, for less of the exposure): the detector's
  // 10 codes cut a few pixels off the full length.
  EXPECT_GT(s.lengthPx, pathPx);
  EXPECT_LE(s.lengthPx, pathPx + kDiameterPx + 1.0);
  // The disc's area times its contrast, less the rim under the detector's 10 codes.
  EXPECT_NEAR(s.energyCodesPx, kContrastCodes * M_PI / 4 * kDiameterPx * kDiameterPx,
              0.1 * kContrastCodes * M_PI / 4 * kDiameterPx * kDiameterPx);
  // The tapered ends cut off read it about a tenth high (167 codes here).
  const double shutter = kShutterOverTau * dropSecondsPerDiameter();
  EXPECT_NEAR(impliedDropContrastCodes(s.energyCodesPx / (s.lengthPx * s.lengthPx), shutter),
              kContrastCodes, 0.15 * kContrastCodes);
}
