// The wind: Stable Fluids steps against analytic cases, stability far beyond CFL, determinism.
#include <gtest/gtest.h>

#include <cmath>

#include "rain/wind_field.h"
#include "util/hash.h"

using namespace pluvia;
using namespace pluvia::rain;

namespace {

WindSettings turbulent(double speed, uint64_t seed = 7) {
  WindSettings s;
  s.speedMetersPerSecond = speed;
  s.directionDeg = 30.0;
  s.gustiness = 1.0;
  s.turbulence = 1.0;
  s.seed = seed;
  return s;
}

}  // namespace

TEST(StableFluidGrid, ProjectionRemovesTheDivergence) {
  StableFluidGrid grid(32, 2.0);
  CounterRng rng(3, 0);
  for (int j = 0; j < grid.size(); ++j)
    for (int i = 0; i < grid.size(); ++i)
      grid.at(i, j) = Eigen::Vector2d(std::sin(2 * M_PI * i / 32.0) + rng.uniform() - 0.5,
                                      std::cos(4 * M_PI * j / 32.0) + rng.uniform() - 0.5);
  const double before = grid.maxDivergence();
  grid.project();
  const double after = grid.maxDivergence();
  std::cout << "max divergence before " << before << " 1/s, after " << after << " 1/s\n";
  EXPECT_GT(before, 0.1);
  EXPECT_LT(after, 1e-7 * before);
}

TEST(WindField, ForcedFieldIsNearlyDivergenceFree) {
  WindField wind(turbulent(10.0));
  for (int k = 0; k < 20; ++k) wind.advance(1.0 / 24.0);
  // Compared with the size of a velocity gradient: RMS over a cell.
  const double scale = 10.0 / wind.fluid().cellSizeMeters();
  EXPECT_LT(wind.fluid().maxDivergence(), 1e-6 * scale);
}

TEST(StableFluidGrid, UniformAndShearFlowsAreCarriedUnchanged) {
  StableFluidGrid grid(16, 1.5);
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) grid.at(i, j) = Eigen::Vector2d(3.0, -2.0);
  for (double dt : {0.37, 5.0, 1000.0}) {
    grid.advect(dt);
    grid.project();
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 16; ++i)
        EXPECT_NEAR((grid.at(i, j) - Eigen::Vector2d(3.0, -2.0)).norm(), 0.0, 1e-12);
  }
  // u = f(z), w = 0: the departure points stay on the node's row, where u is the same.
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i)
      grid.at(i, j) = Eigen::Vector2d(std::sin(2 * M_PI * j / 16.0), 0.0);
  grid.advect(0.9);
  grid.project();
  for (int j = 0; j < 16; ++j)
    for (int i = 0; i < 16; ++i) {
      EXPECT_NEAR(grid.at(i, j).x(), std::sin(2 * M_PI * j / 16.0), 1e-12);
      EXPECT_NEAR(grid.at(i, j).y(), 0.0, 1e-12);
    }
}

TEST(WindField, StableFarBeyondCfl) {
  for (double speed : {0.0, 60.0})
    for (double dt : {1e-4, 1.0 / 24.0, 1.0, 10.0, 100.0}) {
      WindField wind(turbulent(speed));
      const double bound = wind.maxSpeedMetersPerSecond();
      EXPECT_LE(bound, speed * 2.0 + 4.0 * speed);
      double largest = 0.0;
      for (int step = 0; step < 1000; ++step) {
        wind.advance(dt);
        for (double x : {0.0, 13.3, 40.1})
          for (double z : {0.0, -7.7, 55.5}) {
            const Eigen::Vector3d v = wind.velocityAt(x, z);
            ASSERT_TRUE(v.allFinite()) << speed << " " << dt << " " << step;
            largest = std::max(largest, v.norm());
          }
      }
      EXPECT_LE(largest, bound + 1e-9) << speed << " " << dt;
      if (speed == 0.0) {
        EXPECT_EQ(largest, 0.0);
      }
    }
}

TEST(WindField, DeterministicAndZeroStepIsANoOp) {
  WindField a(turbulent(12.0, 99)), b(turbulent(12.0, 99)), other(turbulent(12.0, 100));
  for (int step = 0; step < 50; ++step) {
    const double dt = step % 3 == 0 ? 0.5 : 1.0 / 24.0;
    a.advance(dt);
    b.advance(dt);
    other.advance(dt);
  }
  bool differs = false;
  for (double x = -30.0; x < 30.0; x += 3.7)
    for (double z = -30.0; z < 30.0; z += 4.1) {
      const Eigen::Vector3d v = a.velocityAt(x, z);
      EXPECT_EQ(v, b.velocityAt(x, z));
      differs = differs || v != other.velocityAt(x, z);
      a.advance(0.0);
      EXPECT_EQ(v, a.velocityAt(x, z));
    }
  EXPECT_TRUE(differs);  // the seed matters
  EXPECT_EQ(a.timeSeconds(), b.timeSeconds());
  EXPECT_THROW(a.advance(-1.0), std::exception);
}

TEST(WindField, CalmSettingsGiveTheUniformBaseWind) {
  WindSettings s;
  s.speedMetersPerSecond = 7.0;
  s.directionDeg = 30.0;
  WindField wind(s);
  const Eigen::Vector3d expected(7.0 * std::cos(M_PI / 6), 0.0, -7.0 * std::sin(M_PI / 6));
  for (int step = 0; step < 30; ++step) {
    wind.advance(0.25);
    for (double x : {-100.0, 0.0, 3.3})
      for (double z : {-1.0, 77.0}) EXPECT_EQ(wind.velocityAt(x, z), expected);
  }
  wind.setBase(2.0, 90.0);  // 90 degrees blows toward -Z
  EXPECT_NEAR((wind.velocityAt(1.0, 2.0) - Eigen::Vector3d(0.0, 0.0, -2.0)).norm(), 0.0, 1e-12);
}

TEST(WindField, PeriodicOverTheTile) {
  WindField wind(turbulent(15.0));
  for (int step = 0; step < 24; ++step) wind.advance(1.0 / 24.0);
  const double tile = wind.tileMeters();
  EXPECT_EQ(tile, 64.0);
  for (double x = -50.0; x < 50.0; x += 6.3)
    for (double z = -50.0; z < 50.0; z += 5.9) {
      const Eigen::Vector3d v = wind.velocityAt(x, z);
      EXPECT_NEAR((wind.velocityAt(x + tile, z) - v).norm(), 0.0, 1e-9);
      EXPECT_NEAR((wind.velocityAt(x, z - 3 * tile) - v).norm(), 0.0, 1e-9);
    }
}

TEST(WindField, GustFactorIsSmoothNonNegativeWithMeanOne) {
  WindField wind(turbulent(10.0));
  double sum = 0.0;
  const int n = 400000;
  const double dt = 0.01;
  for (int k = 0; k < n; ++k) {
    const double g = wind.gustFactor(k * dt);
    EXPECT_GE(g, 0.0);
    EXPECT_LE(g, 2.0);
    if (k > 0) {
      EXPECT_LT(std::abs(g - wind.gustFactor((k - 1) * dt)), 0.1);
    }
    sum += g;
  }
  EXPECT_NEAR(sum / n, 1.0, 0.01);
}

TEST(WindField, PerturbationSettlesNearTheRequestedRms) {
  WindSettings s = turbulent(10.0);
  s.gustiness = 0.0;
  s.turbulence = 0.5;
  WindField wind(s);
  for (int step = 0; step < 240; ++step) wind.advance(1.0 / 24.0);
  double sumSquares = 0.0;
  const int n = wind.fluid().size();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) sumSquares += wind.fluid().at(i, j).squaredNorm();
  const double rms = std::sqrt(sumSquares / (n * n));
  std::cout << "perturbation RMS " << rms << " m/s for a requested 5 m/s\n";
  EXPECT_GT(rms, 0.5);
  EXPECT_LT(rms, 10.0);
}
