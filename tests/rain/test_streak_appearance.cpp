// What the shipped lens and physics make of the streaks: the rain layer carries the drops'
// projected area (alpha x area summed over streaks = opacity x (far - near) x the integral of
// N(D) D^2 dD, whatever the defocus and exposure), no thin streak spans a quarter of the frame,
// eddies turn driven rain into more than one direction, the thin lens against its closed form,
// and the rain's extinction and visibility against the Marshall-Palmer integral.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "rain/drop_physics.h"
#include "rain/drop_simulation.h"
#include "rain/thin_lens.h"

using namespace pluvia;
using namespace pluvia::rain;

namespace {

constexpr int kWidth = 640, kHeight = 480;
constexpr double kFovDeg = 36.0;  // the shipped camera
constexpr double kFocusMeters = 20.0, kFNumber = 11.0, kSensorMm = 36.0;

Camera shippedCamera() {
  return Camera::fromFieldOfView(kWidth, kHeight, kFovDeg, 0.0, 1.6);
}

// Integral of Marshall-Palmer N(D) D^k over [dMin, inf) by the midpoint rule, in mm^k / m^3.
double marshallPalmerMoment(double rate, double dMinMm, int k) {
  const double slope = marshallPalmerSlopePerMm(rate);
  double sum = 0.0;
  const double step = 1e-3;
  for (double d = dMinMm + step / 2; d < 20.0; d += step)
    sum += kMarshallPalmerN0 * std::exp(-slope * d) * std::pow(d, k) * step;
  return sum;
}

struct Layer {
  double alphaArea = 0.0;      // sum of alpha x drawn area over streaks, pixels
  double thinTallShare = 0.0;  // of it, in streaks under 2.5 px wide and a quarter frame tall
};

// The streaks of frame 24 at `rate` with the shipped lens (or a pinhole), wind and eddies.
Layer rainLayer(double rate, double windSpeed, bool lens,
                std::vector<rain::StreakInstance>* out = nullptr) {
  const Camera camera = shippedCamera();
  const ThinLens thin = ThinLens::of(camera.focalPx, kWidth, kSensorMm, kFocusMeters, kFNumber);
  DropSimulationSettings s;
  s.firstFrame = 0;
  s.lastFrame = 24;
  s.maxDrops = 2000000;
  s.nearMeters = lens ? std::max(0.3, thin.nearestWithBlurMeters(0.05 * kWidth)) : 0.5;
  s.farMeters = 8.0;
  s.eddyIntensity = 0.2;
  DropSimulation sim(
      s, [camera](double) { return camera; },
      [rate, windSpeed](double) {
        RainAtFrame r;
        r.rateMmPerHour = rate;
        r.windSpeedMetersPerSecond = windSpeed;
        return r;
      });
  sim.advanceTo(24);
  StreakSettings streak;
  streak.exposureSeconds = 0.02;
  if (lens) {
    streak.focusMeters = kFocusMeters;
    streak.fNumber = kFNumber;
    streak.sensorWidthMm = kSensorMm;
  }
  const auto streaks = sim.buildStreaks(streak);
  Layer layer;
  double thinTall = 0.0;
  for (const auto& k : streaks) {
    const double length = std::hypot(k.tailX - k.headX, k.tailY - k.headY) + k.widthPx;
    const double area = double(k.alpha) * k.widthPx * length;
    layer.alphaArea += area;
    if (k.widthPx < 2.5f && std::abs(k.tailY - k.headY) > kHeight / 4.0) thinTall += area;
  }
  layer.thinTallShare = thinTall / layer.alphaArea;
  if (out) *out = streaks;
  return layer;
}

TEST(StreakAppearance, RainLayerCarriesTheDropsProjectedArea) {
  // Each drop's streak carries alpha x area = (f D / z)^2 (its width squared): over a frustum
  // slab of depth dz at z the drops' widths squared sum to n <D^2> W H dz, so the mean alpha of
  // the layer is (far - near) x integral N(D) D^2 dD. The defocus spreads it, never adds to it.
  for (const double rate : {2.0, 8.0, 40.0, 100.0}) {
    const double near = 0.5, far = 8.0;
    const double expected = (far - near) * marshallPalmerMoment(rate, 0.8, 2) * 1e-6;
    const double pinhole = rainLayer(rate, 0.0, false).alphaArea / (kWidth * kHeight);
    const double defocused = rainLayer(rate, 0.0, true).alphaArea / (kWidth * kHeight);
    std::printf("%g mm/h: mean alpha %.5f (pinhole), %.5f (lens), physical %.5f\n", rate, pinhole,
                defocused, expected);
    // 15 %: drops are drawn only while their streak's alpha reaches 1/1024, and the box's
    // margins and the frame's edges cut some streaks.
    EXPECT_NEAR(pinhole / expected, 1.0, 0.15)
        << rate << " mm/h: " << pinhole << " vs " << expected;
    EXPECT_NEAR(defocused / pinhole, 1.0, 0.2) << rate << " mm/h";
  }
}

TEST(StreakAppearance, NoThinStreakSpansAQuarterOfTheFrame) {
  for (const double rate : {8.0, 100.0}) {
    const Layer withLens = rainLayer(rate, 12.0, true);
    const Layer pinhole = rainLayer(rate, 12.0, false);
    std::printf("%g mm/h: thin tall share %.4f with the lens, %.4f with a pinhole\n", rate,
                withLens.thinTallShare, pinhole.thinTallShare);
    EXPECT_LT(withLens.thinTallShare, 0.01) << rate << " mm/h";
    // The measure can fail: without the lens, near drops are wires.
    EXPECT_GT(pinhole.thinTallShare, 0.05) << rate << " mm/h";
  }
}

TEST(StreakAppearance, EddiesSpreadTheDirectionsOfDrivenRain) {
  std::vector<rain::StreakInstance> streaks;
  rainLayer(40.0, 8.0, true, &streaks);
  // Angle of each streak against its neighbours' mean: image direction spread over streaks
  // within one depth band (the same perspective), 2-4 m.
  std::vector<double> angles;
  for (const auto& k : streaks)
    if (k.depthMeters > 2.0f && k.depthMeters < 4.0f)
      angles.push_back(std::atan2(k.tailX - k.headX, k.tailY - k.headY));
  ASSERT_GT(angles.size(), 100u);
  double mean = 0.0, sq = 0.0;
  for (double a : angles) mean += a;
  mean /= double(angles.size());
  for (double a : angles) sq += (a - mean) * (a - mean);
  const double spreadDeg = std::sqrt(sq / double(angles.size())) * 180.0 / M_PI;
  // Eddies of 0.2 x 8 m/s on a fall of about 6 m/s: several degrees, not a hatch of one angle.
  EXPECT_GT(spreadDeg, 4.0);
  EXPECT_LT(spreadDeg, 30.0);
}

TEST(ThinLens, CircleOfConfusionMatchesTheClosedForm) {
  // 55.4 mm at f/11 focused at 20 m on a 36 mm sensor 640 px wide: a point at 1 m blurs over
  // A (s - d) / d * f / (s - f) = 5.04 mm * 19 * 0.002778 = 0.2660 mm = 4.73 px.
  const double focalPx = 0.5 * kWidth / std::tan(0.5 * kFovDeg * M_PI / 180.0);
  const ThinLens lens = ThinLens::of(focalPx, kWidth, kSensorMm, 20.0, 11.0);
  const double focalMm = focalPx * kSensorMm / kWidth;
  const double expectedMm = focalMm / 11.0 * 19.0 * focalMm / (20000.0 - focalMm);
  EXPECT_NEAR(lens.blurPx(1.0), expectedMm * kWidth / kSensorMm, 1e-9);
  EXPECT_EQ(lens.blurPx(20.0), 0.0);
  EXPECT_NEAR(lens.blurPx(lens.nearestWithBlurMeters(12.5)), 12.5, 1e-9);
  EXPECT_FALSE(ThinLens::of(focalPx, kWidth, kSensorMm, 0.0, 11.0).defocuses());
  EXPECT_FALSE(ThinLens::of(focalPx, kWidth, kSensorMm, 0.01, 11.0).defocuses());  // inside f
}

TEST(RainExtinction, MatchesTheMarshallPalmerIntegral) {
  for (const double rate : {1.0, 15.0, 100.0}) {
    // sigma = 2 x integral of N(D) pi D^2 / 4 dD over all drops.
    const double numeric = 2.0 * M_PI / 4.0 * marshallPalmerMoment(rate, 0.0, 2) * 1e-6;
    EXPECT_NEAR(rainExtinctionPerMeter(rate) / numeric, 1.0, 1e-3) << rate;
    EXPECT_NEAR(rainExtinctionPerMeter(rate) * 1e3, 0.365 * std::pow(rate, 0.63),
                0.01 * 0.365 * std::pow(rate, 0.63));
  }
  EXPECT_NEAR(rainVisibilityMeters(15.0), 3.912 / rainExtinctionPerMeter(15.0), 1e-9);
  EXPECT_EQ(rainExtinctionPerMeter(0.0), 0.0);
  EXPECT_EQ(rainVisibilityMeters(0.0), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isfinite(rainVisibilityMeters(1e-9)));
}

}  // namespace
