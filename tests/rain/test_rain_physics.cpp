// Drop sizes, speeds, the drop volume and streak alpha against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "rain/drop_physics.h"
#include "rain/rain_types.h"

using namespace pluvia;
using namespace pluvia::rain;

TEST(DropPhysics, MarshallPalmerCountIsTheClosedFormIntegral) {
  // R = 15 mm/h: Lambda = 4.1 * 15^-0.21.
  const double lambda = 4.1 * std::pow(15.0, -0.21);
  EXPECT_NEAR(marshallPalmerSlopePerMm(15.0), lambda, 1e-12);
  EXPECT_NEAR(dropsPerCubicMeter(15.0, 0.0, 1e9), 8000.0 / lambda, 1e-6);
  EXPECT_NEAR(dropsPerCubicMeter(15.0, 1.0, 2.0),
              8000.0 / lambda * (std::exp(-lambda) - std::exp(-2 * lambda)), 1e-9);
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
  EXPECT_NEAR(terminalVelocityMetersPerSecond(2.0), 9.65 - 10.3 * std::exp(-1.2),
              1e-12);  // about 6.5 m/s
  EXPECT_NEAR(terminalVelocityMetersPerSecond(2.0), 6.55, 0.05);
  EXPECT_EQ(terminalVelocityMetersPerSecond(0.0), 0.0);  // clamped, never negative
  EXPECT_LT(terminalVelocityMetersPerSecond(8.0), 9.65);
}

namespace {

// Composite Simpson on [a, b] with n (even) intervals.
double simpson(const std::function<double(double)>& f, double a, double b, int n = 20000) {
  const double h = (b - a) / n;
  double sum = f(a) + f(b);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(a + i * h);
  return sum * h / 3.0;
}

// The Gamma parameterisation written out again: mu = 2, Marshall–Palmer's D0 (Ulbrich's
// D0 Lambda = 3.67 + mu) and liquid water.
struct ExpectedGamma {
  double n0, lambda;
  explicit ExpectedGamma(double rate) {
    const double mp = 4.1 * std::pow(rate, -0.21);
    lambda = mp * 5.67 / 3.67;
    n0 = 8000.0 * 6.0 * std::pow(lambda, 6) / (120.0 * std::pow(mp, 4));
  }
  double operator()(double d) const { return n0 * d * d * std::exp(-lambda * d); }
};

}  // namespace

TEST(DropPhysics, GammaCountAndMeanDiameterMatchTheIntegrals) {
  for (double rate : {0.01, 4.0, 25.0, 500.0}) {
    for (auto [lo, hi] : {std::pair{0.0, 8.0}, std::pair{0.8, 6.0}, std::pair{2.0, 3.0}}) {
      const ExpectedGamma n(rate);
      const GammaParameters g = gammaParameters(rate);
      EXPECT_DOUBLE_EQ(g.mu, 2.0);
      EXPECT_NEAR(g.slopePerMm, n.lambda, 1e-12 * n.lambda);
      EXPECT_NEAR(g.n0, n.n0, 1e-12 * n.n0);
      const double count = simpson(n, lo, hi);
      EXPECT_NEAR(dropsPerCubicMeter(SizeDistribution::Gamma, rate, lo, hi), count, 1e-9 * count)
          << rate << " " << lo << " " << hi;
      const double mean = simpson([&](double d) { return d * n(d); }, lo, hi) / count;
      double sum = 0.0;
      const int samples = 100000;
      for (int i = 0; i < samples; ++i)
        sum += sampleDiameterMm(SizeDistribution::Gamma, (i + 0.5) / samples, rate, lo, hi);
      EXPECT_NEAR(sum / samples, mean, 1e-4 * mean) << rate << " " << lo << " " << hi;
      EXPECT_DOUBLE_EQ(sampleDiameterMm(SizeDistribution::Gamma, 0.0, rate, lo, hi), lo);
      EXPECT_LE(sampleDiameterMm(SizeDistribution::Gamma, 1.0, rate, lo, hi), hi);
    }
  }
  // The Marshall–Palmer branch is the existing closed form.
  EXPECT_EQ(dropsPerCubicMeter(SizeDistribution::MarshallPalmer, 15.0, 1.0, 2.0),
            dropsPerCubicMeter(15.0, 1.0, 2.0));
  EXPECT_EQ(sampleDiameterMm(SizeDistribution::MarshallPalmer, 0.3, 15.0, 1.0, 2.0),
            sampleDiameterMm(0.3, 15.0, 1.0, 2.0));
}

TEST(DropPhysics, GammaCarriesMarshallPalmersWaterAndRain) {
  for (double rate : {1.0, 15.0, 100.0}) {
    const ExpectedGamma gamma(rate);
    const double mp = marshallPalmerSlopePerMm(rate);
    auto marshall = [&](double d) { return 8000.0 * std::exp(-mp * d); };
    // Liquid water: the third moments agree.
    auto third = [](auto n) { return [n](double d) { return d * d * d * n(d); }; };
    const double water = simpson(third(marshall), 0.0, 60.0);
    EXPECT_NEAR(simpson(third(gamma), 0.0, 60.0), water, 1e-6 * water);
    // Rain rate R = 6e-4 pi int D^3 v(D) N(D) dD: the same within 3 %.
    auto rain = [](auto n) {
      return simpson(
                 [n](double d) { return d * d * d * terminalVelocityMetersPerSecond(d) * n(d); },
                 0.0, 60.0) *
             6e-4 * M_PI;
    };
    EXPECT_NEAR(rain(gamma) / rain(marshall), 1.0, 0.03) << rate;
    // Fewer tiny drops than Marshall–Palmer.
    EXPECT_LT(dropsPerCubicMeter(SizeDistribution::Gamma, rate, 0.0, 0.5),
              dropsPerCubicMeter(rate, 0.0, 0.5));
  }
}

TEST(DropPhysics, GunnKinzerTableAndAtlasAgree) {
  EXPECT_DOUBLE_EQ(gunnKinzerVelocityMetersPerSecond(1.0), 4.03);
  EXPECT_DOUBLE_EQ(gunnKinzerVelocityMetersPerSecond(2.0), 6.49);
  EXPECT_DOUBLE_EQ(gunnKinzerVelocityMetersPerSecond(4.0), 8.83);
  EXPECT_DOUBLE_EQ(gunnKinzerVelocityMetersPerSecond(0.5), 2.06);
  EXPECT_NEAR(gunnKinzerVelocityMetersPerSecond(1.1), 0.5 * (4.03 + 4.64), 1e-12);
  EXPECT_NEAR(gunnKinzerVelocityMetersPerSecond(0.05), 0.27 / 4.0, 1e-12);  // Stokes, v ~ D^2
  EXPECT_EQ(gunnKinzerVelocityMetersPerSecond(0.0), 0.0);
  EXPECT_EQ(gunnKinzerVelocityMetersPerSecond(8.0), 9.17);
  double previous = 0.0;
  for (double d = 0.0; d <= 7.0; d += 0.01) {
    const double v = gunnKinzerVelocityMetersPerSecond(d);
    EXPECT_GE(v, previous);  // monotone
    previous = v;
    if (d >= 1.0 && d <= 5.0) {
      EXPECT_NEAR(terminalVelocityMetersPerSecond(d), v, 0.3) << d;
    }
  }
  EXPECT_EQ(terminalVelocity(VelocityModel::GunnKinzer, 2.0), 6.49);
  EXPECT_EQ(terminalVelocity(VelocityModel::Atlas, 2.0), terminalVelocityMetersPerSecond(2.0));
}

TEST(RainTypes, MizukamiTableOne) {
  EXPECT_EQ(rainTypeNames(), (std::vector<std::string>{"gentle", "hard", "heavy"}));
  struct Row {
    const char* name;
    double rate, diameter, speed;
  };
  for (const Row& row :
       {Row{"gentle", 4.0, 1.0, 4.0}, Row{"hard", 15.0, 1.5, 5.0}, Row{"heavy", 40.0, 2.0, 6.0}}) {
    const RainType* type = findRainType(row.name);
    ASSERT_NE(type, nullptr) << row.name;
    EXPECT_EQ(type->name, row.name);
    EXPECT_EQ(type->rateMmH, row.rate);
    EXPECT_EQ(type->meanDiameterMm, row.diameter);
    EXPECT_EQ(type->speedMetersPerSecond, row.speed);
  }
  EXPECT_EQ(findRainType("drizzle"), nullptr);
}

TEST(DropPhysics, DistributionsFiniteFromNoRainToFiveHundred) {
  for (SizeDistribution distribution :
       {SizeDistribution::MarshallPalmer, SizeDistribution::Gamma}) {
    EXPECT_EQ(dropsPerCubicMeter(distribution, 0.0, 0.5, 6.0), 0.0);
    for (double rate : {0.0, 1e-9, 0.01, 500.0})
      for (double hi : {6.0, 1e9}) {
        const double count = dropsPerCubicMeter(distribution, rate, 0.5, hi);
        EXPECT_TRUE(std::isfinite(count));
        EXPECT_GE(count, 0.0);
        for (double u : {0.0, 1e-12, 0.5, 1.0 - 1e-12}) {
          const double d = sampleDiameterMm(distribution, u, rate, 0.5, hi);
          EXPECT_TRUE(std::isfinite(d)) << rate << " " << u;
          EXPECT_GE(d, 0.5);
          EXPECT_LE(d, hi);
        }
      }
  }
}

TEST(DropOscillation, GargNayarFrequency) {
  // Rayleigh's mode (2, 0): a 1/60 s period at r0 = 1.6 mm (diameter 3.2 mm), f ~ r0^-3/2.
  EXPECT_NEAR(rain::oscillationFrequencyHz(3.2), 60.0, 0.3);
  EXPECT_NEAR(rain::oscillationFrequencyHz(0.8) / rain::oscillationFrequencyHz(3.2), 8.0, 1e-9);
  EXPECT_EQ(rain::oscillationFrequencyHz(0.0), 0.0);
}
