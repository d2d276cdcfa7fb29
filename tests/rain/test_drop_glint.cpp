// The oscillating drop's glint (rain/drop_glint.h, localLightBead in rain/streak_types.h):
// the curvature factors against a numerical surface, the bead's closed forms, its light and view
// dependence and its normalisation.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <utility>

#include <Eigen/Geometry>

#include "rain/drop_glint.h"

namespace pluvia::rain {
namespace {

// The Gaussian curvature of r(theta, phi) = 1 + eps P(cos theta) cos(m phi) at (theta, phi), by
// central differences of the embedding X = r (sin theta cos phi, cos theta, sin theta sin phi)
// and the fundamental forms: an independent reference for the first-order factor.
template <typename Legendre>
double gaussianCurvature(double eps, int m, Legendre legendre, double theta, double phi) {
  auto point = [&](double t, double p) {
    const double r = 1.0 + eps * legendre(std::cos(t)) * std::cos(m * p);
    return Eigen::Vector3d(r * std::sin(t) * std::cos(p), r * std::cos(t),
                           r * std::sin(t) * std::sin(p));
  };
  const double h = 1e-4;
  const Eigen::Vector3d x = point(theta, phi);
  const Eigen::Vector3d xt = (point(theta + h, phi) - point(theta - h, phi)) / (2 * h);
  const Eigen::Vector3d xp = (point(theta, phi + h) - point(theta, phi - h)) / (2 * h);
  const Eigen::Vector3d xtt = (point(theta + h, phi) - 2 * x + point(theta - h, phi)) / (h * h);
  const Eigen::Vector3d xpp = (point(theta, phi + h) - 2 * x + point(theta, phi - h)) / (h * h);
  const Eigen::Vector3d xtp = (point(theta + h, phi + h) - point(theta + h, phi - h) -
                               point(theta - h, phi + h) + point(theta - h, phi - h)) /
                              (4 * h * h);
  const Eigen::Vector3d n = xt.cross(xp).normalized();
  const double E = xt.dot(xt), F = xt.dot(xp), G = xp.dot(xp);
  const double L = xtt.dot(n), M = xtp.dot(n), N = xpp.dot(n);
  return (L * N - M * M) / (E * G - F * F);
}

double legendre20(double x) {
  return 0.5 * (3 * x * x - 1);
}
double legendre31(double x) {
  return 1.5 * (5 * x * x - 1) * std::sqrt(1 - x * x);
}

TEST(DropGlint, CurvatureFactorsMatchANumericalSurface) {
  // ln K moves by (n - 1)(n + 2) eps P cos(m phi): 4 for (2, 0), 10 for (3, 1), to 1 % of the
  // first-order term at eps = 1e-4, give or take the second-order term (under 50 eps^2).
  const double eps = 1e-4;
  for (double theta : {0.3, 0.9, 1.4, 2.2}) {
    for (double phi : {0.2, 1.1}) {
      const double k20 = gaussianCurvature(eps, 0, legendre20, theta, phi);
      const double expected20 = 4 * eps * legendre20(std::cos(theta));
      EXPECT_NEAR(std::log(k20), expected20, 0.01 * std::abs(expected20) + 50 * eps * eps)
          << "theta " << theta;
      const double k31 = gaussianCurvature(eps, 1, legendre31, theta, phi);
      const double expected31 = 10 * eps * legendre31(std::cos(theta)) * std::cos(phi);
      EXPECT_NEAR(std::log(k31), expected31, 0.01 * std::abs(expected31) + 50 * eps * eps)
          << "theta " << theta << " phi " << phi;
    }
  }
  // A sphere of radius 1 + eps (n = 0): K = (1 + eps)^-2, the factor -2 = (0 - 1)(0 + 2).
  EXPECT_NEAR(gaussianCurvature(
                  eps, 0, [](double) { return 1.0; }, 0.7, 0.3),
              1.0 / ((1 + eps) * (1 + eps)), 1e-6);
}

TEST(DropGlint, GlintModesFollowTheHalfVector) {
  // h vertical: only mode (2, 0), at its pole value; at the magic angle mode (2, 0) is gone; at
  // the equator (2, 0) is -1/2 and (3, 1) is -3/2 of their amplitudes (times 4 and 10).
  auto atPole = glintModes(0.2f, 0.1f, 1.0);
  EXPECT_NEAR(atPole[0], 0.8f, 1e-6);
  EXPECT_NEAR(atPole[1], 0.0f, 1e-6);
  auto magic = glintModes(0.2f, 0.1f, 1.0 / std::sqrt(3.0));
  EXPECT_NEAR(magic[0], 0.0f, 1e-6);
  auto equator = glintModes(0.2f, 0.1f, 0.0);
  EXPECT_NEAR(equator[0], -0.4f, 1e-6);
  EXPECT_NEAR(equator[1], -1.5f, 1e-6);
  // (3, 1) vanishes where 5 x^2 = 1 too (63.4 deg from the vertical).
  EXPECT_NEAR(glintModes(0.2f, 0.1f, 1.0 / std::sqrt(5.0))[1], 0.0f, 1e-6);
}

TEST(DropGlint, TheBeadIsExpOfMinusTheLogCurvature) {
  // parabolicSine is within 0.056 of sin(2 pi s) and exact at its zeros and extremes.
  for (int i = 0; i <= 400; ++i) {
    const float s = -2.0f + i / 100.0f;
    EXPECT_NEAR(parabolicSine(s), std::sin(2 * M_PI * s), 0.057) << s;
  }
  EXPECT_NEAR(parabolicSine(0.25f), 1.0f, 1e-6);
  EXPECT_NEAR(parabolicSine(0.75f), -1.0f, 1e-6);
  // Without modes the bead is 1; with small ones exp(-x) to second order (x^3 / 6 left).
  EXPECT_EQ(localLightBead(3.0f, 0.4f, 0.0f, 0.0f, 0.7f), 1.0f);
  for (float v : {0.0f, 0.13f, 0.5f, 0.91f}) {
    const float s = 0.2f + 1.5f * v;
    const double x = 0.05 * parabolicSine(s) - 0.03 * parabolicSine(kOscillationModeRatio * s);
    EXPECT_NEAR(localLightBead(1.5f, 0.2f, 0.05f, -0.03f, v), std::exp(-x), std::pow(0.08, 3) / 6);
  }
  // Positive and finite for any amplitude the simulation or a hostile streak could carry.
  for (float mode : {-1e4f, -30.0f, 30.0f, 1e4f}) {
    const float bead = localLightBead(1.0f, 0.25f, mode, mode, 0.0f);
    EXPECT_TRUE(std::isfinite(bead) && bead > 0.0f) << mode;
  }
  // Mode (2, 0) alone: period 1 / cycles along the streak.
  EXPECT_NEAR(localLightBead(2.0f, 0.1f, 0.8f, 0.0f, 0.3f),
              localLightBead(2.0f, 0.1f, 0.8f, 0.0f, 0.8f), 1e-5);
}

TEST(DropGlint, TheMeanOverPhasesMatchesABruteForceAverage) {
  // Two independent phases on a 400 x 400 midpoint grid, the bead evaluated as it is drawn.
  for (const auto& [mode20, mode31] : {std::pair{0.8f, 0.0f}, std::pair{-0.4f, -1.5f},
                                       std::pair{0.3f, 2.07f}, std::pair{0.0f, 0.0f}}) {
    const int n = 400;
    double sum = 0.0;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double x =
            mode20 * parabolicSine((i + 0.5f) / n) + mode31 * parabolicSine((j + 0.5f) / n);
        sum += std::sqrt(1.0 + x * x) - x;
      }
    EXPECT_NEAR(oscillationMeanBead(mode20, mode31), sum / (n * n), 1e-4)
        << mode20 << " " << mode31;
  }
}

TEST(DropGlint, ShapeGlintKeepsTheMeanAndShortExposuresSpreadDrops) {
  // A lamp straight above a drop seen level: h at 45 deg from the vertical.
  StreakInstance streak{};
  streak.localR = 2.0f, streak.localG = 1.0f, streak.localB = 0.5f;
  streak.beadCycles = 0.1f;  // 1/1000 s of a 100 Hz drop
  streak.glintMode20 = 0.2f, streak.glintMode31 = 0.1f;
  shapeGlint(streak, {0, 1, 0}, {0, 0, 1}, {0, 1, 0});
  const auto expected = glintModes(0.2f, 0.1f, std::sqrt(0.5));
  EXPECT_NEAR(streak.glintMode20, expected[0], 1e-6);
  EXPECT_NEAR(streak.glintMode31, expected[1], 1e-6);
  const float mean = oscillationMeanBead(expected[0], expected[1]);
  EXPECT_GT(mean, 1.0f);  // sqrt(1 + x^2) - x averages above 1
  EXPECT_NEAR(streak.localR * mean, 2.0f, 1e-5);
  EXPECT_NEAR(streak.localB * mean, 0.5f, 1e-5);
  // Over many drops (phases) the normalised glint averages to the sphere's; within one short
  // exposure it barely beads, so drops differ: their means spread by tens of per cent.
  double sum = 0.0, low = 1e9, high = 0.0;
  // Drops have fallen for many periods: their starting phases spread over hundreds of them
  // (two modes whose ratio is near 2 need that to meet in every relative phase).
  const int drops = 4000;
  for (int i = 0; i < drops; ++i) {
    const float phase = (i + 0.5f) / drops * 400.0f;
    const double b = streakMeanBead(0.1f, phase, streak.glintMode20, streak.glintMode31) / mean;
    sum += b, low = std::min(low, b), high = std::max(high, b);
  }
  EXPECT_NEAR(sum / drops, 1.0, 0.01);
  EXPECT_GT(high / low, 1.5);
  // Light straight behind the drop: h falls back to the view direction, still finite.
  StreakInstance behind = streak;
  behind.glintMode20 = 0.2f, behind.glintMode31 = 0.1f;
  shapeGlint(behind, {0, 0, -1}, {0, 0, 1}, {0, 1, 0});
  EXPECT_TRUE(std::isfinite(behind.localR) && std::isfinite(behind.glintMode20));
}

}  // namespace
}  // namespace pluvia::rain
