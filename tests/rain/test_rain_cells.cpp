// Rain cells: the Gaussian density and size, motion with the wind, the pool bound.
#include <gtest/gtest.h>

#include <cmath>

#include "rain/rain_cells.h"

using namespace pluvia::rain;

namespace {

WindSettings uniformWind(double speed, double directionDeg) {
  WindSettings s;
  s.speedMetersPerSecond = speed;
  s.directionDeg = directionDeg;
  return s;
}

}  // namespace

TEST(RainCells, GaussianDensityAndSize) {
  RainCellSettings s;
  s.count = 1;
  s.radiusMeters = 5.0;
  s.peakDensity = 4.0;
  s.sizeScale = 1.3;
  RainCells cells(s, Eigen::Vector2d(10.0, -3.0));
  ASSERT_EQ(cells.centersXZ().size(), 1u);
  const Eigen::Vector2d c = cells.centersXZ()[0];
  EXPECT_LE((c - Eigen::Vector2d(10.0, -3.0)).cwiseAbs().maxCoeff(), s.regionHalfSizeMeters);
  EXPECT_DOUBLE_EQ(cells.densityFactor(c.x(), c.y()), 4.0);
  EXPECT_DOUBLE_EQ(cells.sizeFactor(c.x(), c.y()), 1.3);
  // One sigma away along any direction.
  const double oneSigma = 1.0 + 3.0 * std::exp(-0.5);
  EXPECT_NEAR(cells.densityFactor(c.x() + 5.0, c.y()), oneSigma, 1e-12);
  EXPECT_NEAR(cells.densityFactor(c.x() + 3.0, c.y() - 4.0), oneSigma, 1e-12);
  EXPECT_NEAR(cells.sizeFactor(c.x(), c.y() + 5.0), 1.0 + 0.3 * std::exp(-0.5), 1e-12);
  EXPECT_NEAR(cells.densityFactor(c.x() + 200.0, c.y()), 1.0, 1e-12);
  EXPECT_NEAR(cells.sizeFactor(c.x() + 200.0, c.y()), 1.0, 1e-12);
}

TEST(RainCells, CentresMoveWithAUniformWind) {
  RainCellSettings s;
  s.count = 5;
  s.regionHalfSizeMeters = 1000.0;  // no wrap within this test
  RainCells cells(s, Eigen::Vector2d::Zero());
  WindField wind(uniformWind(8.0, 45.0));
  const auto start = cells.centersXZ();
  const Eigen::Vector2d v(8.0 * std::cos(M_PI / 4), -8.0 * std::sin(M_PI / 4));
  for (int step = 0; step < 10; ++step) {
    wind.advance(0.5);
    cells.advance(0.5, wind);
  }
  for (size_t k = 0; k < start.size(); ++k)
    EXPECT_NEAR((cells.centersXZ()[k] - (start[k] + 5.0 * v)).norm(), 0.0, 1e-9);
}

TEST(RainCells, CentresWrapInTheirRegion) {
  RainCellSettings s;
  s.count = 8;
  s.regionHalfSizeMeters = 30.0;
  const Eigen::Vector2d origin(100.0, 50.0);
  RainCells cells(s, origin);
  WindSettings w = uniformWind(20.0, 200.0);
  w.turbulence = 0.5;
  WindField wind(w);
  for (int step = 0; step < 200; ++step) {
    wind.advance(0.25);
    cells.advance(0.25, wind);
    for (const Eigen::Vector2d& c : cells.centersXZ())
      EXPECT_LE((c - origin).cwiseAbs().maxCoeff(), 30.0 + 1e-9);
  }
}

TEST(RainCells, NoCellsMeansOne) {
  RainCells cells(RainCellSettings{}, Eigen::Vector2d(3.0, 4.0));
  EXPECT_TRUE(cells.centersXZ().empty());
  EXPECT_EQ(cells.maxDensityFactor(), 1.0);
  for (double x = -50.0; x <= 50.0; x += 10.0)
    for (double z = -50.0; z <= 50.0; z += 10.0) {
      EXPECT_EQ(cells.densityFactor(x, z), 1.0);
      EXPECT_EQ(cells.sizeFactor(x, z), 1.0);
    }
}

TEST(RainCells, MaxDensityFactorBoundsTheDensity) {
  RainCellSettings s;
  s.count = 6;
  s.radiusMeters = 8.0;
  s.peakDensity = 5.0;
  s.regionHalfSizeMeters = 10.0;  // crowded: the cells overlap
  RainCells cells(s, Eigen::Vector2d::Zero());
  WindSettings w = uniformWind(10.0, 0.0);
  w.turbulence = 1.0;
  WindField wind(w);
  double largest = 0.0;
  for (int step = 0; step < 50; ++step) {
    for (double x = -20.0; x <= 20.0; x += 0.5)
      for (double z = -20.0; z <= 20.0; z += 0.5) {
        largest = std::max(largest, cells.densityFactor(x, z));
        EXPECT_LE(cells.sizeFactor(x, z), s.sizeScale + 1e-12);
      }
    wind.advance(0.2);
    cells.advance(0.2, wind);
  }
  EXPECT_LE(largest, cells.maxDensityFactor());
  EXPECT_GT(largest, s.peakDensity);  // overlapping cells do add up
}
