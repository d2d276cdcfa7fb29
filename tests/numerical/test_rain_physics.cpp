// Drop sizes, speeds, the drop volume and streak alpha against closed forms.
#include <gtest/gtest.h>

#include <cmath>

#include "rain/drop_physics.h"
#include "rain/drop_volume.h"

using namespace pluvia;
using namespace pluvia::rain;

TEST(DropPhysics, MarshallPalmerCountIsTheClosedFormIntegral) {
  // R = 15 mm/h: Lambda = 4.1 * 15^-0.21.
  const double lambda = 4.1 * std::pow(15.0, -0.21);
  EXPECT_NEAR(marshallPalmerSlopePerMm(15.0), lambda, 1e-12);
  EXPECT_NEAR(dropsPerCubicMeter(15.0, 0.0, 1e9), 8000.0 / lambda, 1e-6);
  EXPECT_NEAR(dropsPerCubicMeter(15.0, 1.0, 2.0), 8000.0 / lambda * (std::exp(-lambda) - std::exp(-2 * lambda)), 1e-9);
  EXPECT_EQ(dropsPerCubicMeter(0.0, 0.5, 6.0), 0.0);
  // Heavier rain has more large drops.
  EXPECT_GT(dropsPerCubicMeter(40.0, 2.0, 6.0), dropsPerCubicMeter(4.0, 2.0, 6.0));
}

TEST(DropPhysics, SampledDiametersFollowTheTruncatedExponential) {
  const double rate = 25.0, lo = 0.8, hi = 6.0;
  const double lambda = marshallPalmerSlopePerMm(rate);
  // Mean of the exponential truncated to [lo, hi].
  const double a = std::exp(-lambda * lo), b = std::exp(-lambda * hi);
  const double mean = (lo * a - hi * b) / (a - b) + 1.0 / lambda;
  double sum = 0.0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) sum += sampleDiameterMm((i + 0.5) / n, rate, lo, hi);
  EXPECT_NEAR(sum / n, mean, 1e-3);
  EXPECT_DOUBLE_EQ(sampleDiameterMm(0.0, rate, lo, hi), lo);
  EXPECT_LE(sampleDiameterMm(0.999999999, rate, lo, hi), hi);
}

TEST(DropPhysics, AtlasTerminalVelocity) {
  EXPECT_NEAR(terminalVelocityMetersPerSecond(2.0), 9.65 - 10.3 * std::exp(-1.2), 1e-12);  // about 6.5 m/s
  EXPECT_NEAR(terminalVelocityMetersPerSecond(2.0), 6.55, 0.05);
  EXPECT_EQ(terminalVelocityMetersPerSecond(0.0), 0.0);  // clamped, never negative
  EXPECT_LT(terminalVelocityMetersPerSecond(8.0), 9.65);
}

TEST(DropVolume, SteadyCountDeterministicAndWrapped) {
  Camera camera = Camera::fromFieldOfView(320, 240, 40, 10, 1.6);
  DropVolumeParams params;
  params.rainRateMmPerHour = 20;
  params.maxDrops = 5000;
  DropVolume a(camera, params), b(camera, params);
  ASSERT_EQ(a.drops().size(), 5000u);
  for (size_t i = 0; i < a.drops().size(); i += 97) {
    for (double t : {0.0, 1.7, 1000.0}) {
      Eigen::Vector3d p = a.positionAt(i, t);
      EXPECT_EQ(p, b.positionAt(i, t));
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_GE(p[axis], a.boxMin()[axis] - 1e-9);
        EXPECT_LE(p[axis], a.boxMin()[axis] + a.boxSize()[axis] + 1e-9);
      }
    }
  }
  // The number of drops drawn in view stays steady from frame to frame (no jumps).
  StreakParams streak;
  size_t previous = buildStreaks(a, camera, 0.0, streak).size();
  for (int frame = 1; frame < 48; ++frame) {
    size_t count = buildStreaks(a, camera, frame / 24.0, streak).size();
    EXPECT_NEAR(double(count), double(previous), 0.1 * previous) << "frame " << frame;
    previous = count;
  }
}

TEST(DropVolume, StreakAlphaIsDiameterOverStreakLength) {
  // One drop falling across the view 5 m in front of an untilted camera.
  Camera camera = Camera::fromFieldOfView(640, 480, 60, 0, 1.6);
  DropVolumeParams params;
  params.rainRateMmPerHour = 10;
  params.maxDrops = 20000;
  params.nearMeters = 4.9;
  params.farMeters = 5.1;
  DropVolume volume(camera, params);
  StreakParams streak;
  streak.exposureSeconds = 0.01;
  streak.minWidthPx = 0.0;  // no minimum width: alpha is the pure time fraction
  auto streaks = buildStreaks(volume, camera, 0.0, streak);
  ASSERT_FALSE(streaks.empty());
  for (const auto& s : streaks) {
    const double length = std::hypot(s.tailX - s.headX, s.tailY - s.headY);
    const double expected = std::min(1.0, s.widthPx / std::max<double>(length, s.widthPx));
    EXPECT_NEAR(s.alpha, expected, 1e-5);
    // Garg and Nayar: 2r / (v T) for motion across the view.
    EXPECT_GT(s.tailY, s.headY);  // falling means moving down the image
  }
}

TEST(DropVolume, ExtremesStayFinite) {
  Camera camera = Camera::fromFieldOfView(64, 48, 36, 0, 1.6);
  for (double rate : {0.0, 0.01, 500.0}) {
    DropVolumeParams params;
    params.rainRateMmPerHour = rate;
    params.maxDrops = 3000;
    params.windMetersPerSecond = Eigen::Vector3d(60, 0, 0);
    DropVolume volume(camera, params);
    for (double exposure : {1.0 / 8000.0, 1.0}) {
      StreakParams streak;
      streak.exposureSeconds = exposure;
      for (const auto& s : buildStreaks(volume, camera, 12.5, streak)) {
        for (float v : {s.headX, s.headY, s.tailX, s.tailY, s.widthPx, s.alpha, s.depthMeters}) EXPECT_TRUE(std::isfinite(v));
        EXPECT_GT(s.alpha, 0.0f);
        EXPECT_LE(s.alpha, 1.0f);
      }
    }
  }
}
