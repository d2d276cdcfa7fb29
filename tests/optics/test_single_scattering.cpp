// Single scattering around local lights (optics/single_scattering.h): the three integrals against
// closed forms, the tables against the integrals, the table-based radiance against the marched
// reference and both against the thin-medium closed form, and every extreme finite.
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "optics/single_scattering.h"

namespace pluvia::optics {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3 unit(Vec3 v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}

const ScatteringTables& tables() {
  static const ScatteringTables t;
  return t;
}

double quadrature(ScatteringIntegral which, double u, double v) {
  return scatteringIntegral(which, u, 0.0, v);
}

TEST(SingleScattering, IntegralsMatchClosedForms) {
  using enum ScatteringIntegral;
  for (double v : {0.1, 0.7, 1.3, kPi / 2}) {
    EXPECT_NEAR(quadrature(F, 0, v), v, 1e-10);
    EXPECT_NEAR(quadrature(S, 0, v), (1 - std::cos(2 * v)) / 2, 1e-10);
    EXPECT_NEAR(quadrature(C, 0, v), std::sin(2 * v) / 2, 1e-10);
  }
  // Large u: F -> 1/u, S -> 2/u^2, C -> 1/u (the integrand lives near e = 0).
  EXPECT_NEAR(quadrature(F, 1e4, 1.0) * 1e4, 1.0, 1e-3);
  EXPECT_NEAR(quadrature(S, 1e4, 1.0) * 1e8, 2.0, 1e-2);
  EXPECT_NEAR(quadrature(C, 1e4, 1.0) * 1e4, 1.0, 1e-3);
  // The scale folds in without overflow: exp(700) times exp(-700)-sized integrand.
  EXPECT_NEAR(scatteringIntegral(F, 700, 0.7854, 1.0, 700 * std::tan(0.7854)),
              std::cos(0.7854) * std::cos(0.7854) / 700, 1e-5);
}

TEST(SingleScattering, TablesMatchTheQuadrature) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> logU(-3, 3), e(0.0, kPi / 2);
  double worst = 0;
  for (int i = 0; i < 300; ++i) {
    const double u = std::pow(10.0, logU(random));
    double e0 = e(random), e1 = e(random);
    if (e1 < e0) std::swap(e0, e1);
    // Relative to the integral from e0 on (what the ray from there gathers).
    const double logScale = u * std::tan(e0) + std::log1p(u);
    for (auto which : {ScatteringIntegral::F, ScatteringIntegral::S, ScatteringIntegral::C}) {
      const double reference = scatteringIntegral(which, u, e0, e1, logScale);
      const double table = tables().integral(which, u, e0, e1, logScale);
      worst = std::max(worst, std::abs(table - reference));
    }
  }
  // The scaled integrals are O(1); bilinear on 128 x 128 keeps them to about 1e-3.
  EXPECT_LT(worst, 2e-3);
}

TEST(SingleScattering, ThinMediumMatchesTheUnattenuatedClosedForm) {
  // beta -> 0: L = beta / (4 pi) integral dx / d^2 = beta (pi - gamma) / (4 pi D sin gamma).
  const double beta = 1e-5;
  LocalLight light;
  light.positionMeters = {3, 1, 8};
  const double distance = std::sqrt(9 + 1 + 64.0);
  for (Vec3 ray : {Vec3{0, 0, 1}, unit({1, 0, 1}), unit({0, 1, -1}), unit({-1, 0, 0})}) {
    const double cosGamma = (ray[0] * 3 + ray[1] * 1 + ray[2] * 8) / distance;
    const double gamma = std::acos(cosGamma);
    const double expected = beta * (kPi - gamma) / (4 * kPi * distance * std::sin(gamma));
    const double inf = std::numeric_limits<double>::infinity();
    EXPECT_NEAR(inscatteredRadianceReference(light, ray, inf, beta), expected, 2e-3 * expected);
    EXPECT_NEAR(inscatteredRadiance(tables(), light, ray, inf, beta), expected, 1e-2 * expected);
  }
}

// Error over a grid of camera rays for one light and medium, as an image shows it: the summed
// absolute error over the summed reference, and the worst single ray against the brightest.
struct GridError {
  double summed = 0;
  double worstOverPeak = 0;
  int lit = 0;
};
GridError gridError(const LocalLight& light, double beta, double length) {
  double sumError = 0, sumReference = 0, peak = 0, worstError = 0;
  GridError result;
  for (double x = -0.6; x <= 0.61; x += 0.1)
    for (double y = -0.6; y <= 0.61; y += 0.1) {
      const Vec3 ray = unit({x + 0.013, y + 0.007, 1});  // never straight through a light
      const double reference = inscatteredRadianceReference(light, ray, length, beta);
      const double fast = inscatteredRadiance(tables(), light, ray, length, beta);
      sumError += std::abs(fast - reference);
      sumReference += reference;
      peak = std::max(peak, reference);
      worstError = std::max(worstError, std::abs(fast - reference));
      if (reference > 0) ++result.lit;
    }
  result.summed = sumReference > 0 ? sumError / sumReference : 0;
  result.worstOverPeak = peak > 0 ? worstError / peak : 0;
  return result;
}

TEST(SingleScattering, PointLightTablesWithinOnePercentOfTheMarch) {
  const double inf = std::numeric_limits<double>::infinity();
  LocalLight light;
  for (double beta : {0.01, 0.1, 1.0})
    for (Vec3 position : {Vec3{2, 3, 10}, Vec3{-1, 0.5, 4}, Vec3{0.3, 0, 1.5}, Vec3{0, 1, -2}})
      for (double length : {inf, 6.0, 1.0}) {
        light.positionMeters = position;
        const GridError error = gridError(light, beta, length);
        EXPECT_LT(error.summed, 0.01) << beta << " " << position[2] << " " << length;
        EXPECT_LT(error.worstOverPeak, 0.01) << beta << " " << position[2] << " " << length;
      }
}

TEST(SingleScattering, SpotlightTablesWithinTwoPercentOfTheMarch) {
  const double inf = std::numeric_limits<double>::infinity();
  LocalLight light;
  light.spot = true;
  light.positionMeters = {1, 3, 8};
  light.axis = unit({-0.2, -1, 0.1});
  for (double halfAngleDeg : {3.0, 20.0, 45.0, 80.0})
    for (double q : {0.0, 0.5, 1.0})
      for (double beta : {0.05, 0.5}) {
        light.cosHalfAngle = std::cos(halfAngleDeg * kPi / 180);
        light.falloffQ = q;
        const GridError error = gridError(light, beta, inf);
        EXPECT_GT(error.lit, halfAngleDeg < 10 ? 3 : 10)
            << halfAngleDeg;  // the beam crosses the view
        EXPECT_LT(error.summed, 0.02) << halfAngleDeg << " " << q << " " << beta;
        EXPECT_LT(error.worstOverPeak, 0.02) << halfAngleDeg << " " << q << " " << beta;
      }
}

TEST(SingleScattering, OccluderCutsTheGlowAndTheBeam) {
  LocalLight light;
  light.positionMeters = {0.5, 0, 10};
  const Vec3 ray{0, 0, 1};
  // A wall at 5 m hides the lamp's neighbourhood: much less than the open ray, more than 0.
  const double open = inscatteredRadiance(tables(), light, ray, 1e9, 0.1);
  const double walled = inscatteredRadiance(tables(), light, ray, 5.0, 0.1);
  EXPECT_GT(walled, 0);
  EXPECT_LT(walled, 0.2 * open);
  // Monotone in the ray's length.
  double previous = 0;
  for (double length = 1; length < 40; length += 1.5) {
    const double now = inscatteredRadiance(tables(), light, ray, length, 0.1);
    EXPECT_GE(now, previous - 1e-12);
    previous = now;
  }
}

TEST(SingleScattering, ExtremesAreFiniteAndNonNegative) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<LocalLight> lights;
  for (Vec3 position : {Vec3{0, 0, 0}, Vec3{0, 0, 1e-9}, Vec3{0, 0, -3}, Vec3{0, 0, 5},
                        Vec3{1e4, 0, 1}, Vec3{0.01, 0, 0.5}}) {
    LocalLight point;
    point.positionMeters = position;
    lights.push_back(point);
    for (double halfAngle : {1e-6, 0.01, 0.5, kPi / 2 - 1e-9, kPi / 2})
      for (double q : {0.0, 1.0}) {
        LocalLight spot = point;
        spot.spot = true;
        spot.axis = {0, 0, -1};
        spot.cosHalfAngle = std::cos(halfAngle);
        spot.falloffQ = q;
        lights.push_back(spot);
      }
  }
  for (const auto& light : lights)
    for (Vec3 ray : {Vec3{0, 0, 1}, Vec3{0, 0, -1}, unit({1, 0, 1}), Vec3{1, 0, 0}})
      for (double beta : {1e-9, 0.01, 1.0, 100.0})
        for (double length : {inf, 0.0, 1e-6, 2.0}) {
          const double value = inscatteredRadiance(tables(), light, ray, length, beta);
          EXPECT_TRUE(std::isfinite(value));
          EXPECT_GE(value, 0.0);
        }
}

}  // namespace
}  // namespace pluvia::optics
