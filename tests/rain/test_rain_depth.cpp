// How deep a camera sees rain as streaks (rain/rain_depth.h), against the closed forms:
// Marshall-Palmer's median-volume diameter D0 = 3.67 / Lambda, Lambda = 4.1 R^-0.21 per mm, and
// the depth 2 f D0 (twice the depth at which that drop is one pixel wide).
#include <gtest/gtest.h>

#include <cmath>

#include "rain/rain_depth.h"

using namespace pluvia::rain;

TEST(RainDepth, MedianVolumeDiameterFollowsMarshallPalmer) {
  EXPECT_NEAR(medianVolumeDiameterMm(1.0), 3.67 / 4.1, 1e-12);
  // D0 grows as R^0.21: 8 mm/h against 1 mm/h.
  EXPECT_NEAR(medianVolumeDiameterMm(8.0) / medianVolumeDiameterMm(1.0), std::pow(8.0, 0.21),
              1e-12);
  EXPECT_NEAR(medianVolumeDiameterMm(8.0), 1.385, 0.001);
}

TEST(RainDepth, CountsInPixelsNotMetres) {
  // A 50 degree view 640 px wide: f = 320 / tan(25 deg) = 686.2 px; 8 mm/h: 1.90 m.
  const double focalPx = 320.0 / std::tan(25.0 * M_PI / 180.0);
  const double depth = streakDepthMeters(focalPx, 8.0);
  EXPECT_NEAR(depth, kVisibleDepthOverOnePixel * focalPx * 1e-3 * medianVolumeDiameterMm(8.0),
              1e-12);
  EXPECT_NEAR(depth, 1.90, 0.01);
  // Three times the pixels (1920 px), three times as deep; drops drawn twice as big, twice as deep;
  // heavier rain (bigger drops) deeper.
  EXPECT_NEAR(streakDepthMeters(3.0 * focalPx, 8.0), 3.0 * depth, 1e-12);
  EXPECT_NEAR(streakDepthMeters(focalPx, 8.0, 2.0), 2.0 * depth, 1e-12);
  EXPECT_GT(streakDepthMeters(focalPx, 40.0), depth);
  EXPECT_LT(streakDepthMeters(focalPx, 1.5), depth);
}
