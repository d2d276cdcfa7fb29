// The Monte-Carlo drop tracer against energy conservation, the undeviated view through a drop of
// index ~1, and 1-D quadratures over the impact parameter of the deviation of each ray order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

#include "image/equirect.h"
#include "independent_fresnel.h"
#include "optics/drop_trace.h"
#include "test_support.h"

using namespace pluvia;
using namespace pluvia::optics;

namespace {

using Vec = std::array<double, 3>;

double dot(const Vec& a, const Vec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec unit(const Vec& a) {
  const double n = std::sqrt(dot(a, a));
  return {a[0] / n, a[1] / n, a[2] / n};
}

// A grey map that depends only on the cosine between a direction and the view.
EquirectMap mapAroundView(const Vec& view, const std::function<double(double)>& f) {
  return test::equirectOf(1024, 512, [&](const Vec& d) {
    const double l = f(dot(d, view));
    return Vec{l, l, l};
  });
}

// Disc-averaged radiance of a drop in an environment L(w) = f(w . view), by the midpoint rule in
// b^2 = sin^2 i: the external reflection leaves at deviation pi - 2i from the view direction,
// the part refracted out after k internal reflections at 2(i - r) + k(pi - 2r), with power
// (1 - R)^2 R^k (the internal reflectance equals the external one, R(i)). A path of
// maxInteractions interfaces reaches k = maxInteractions - 2.
double deviationQuadrature(double eta, int maxInteractions,
                           const std::function<double(double)>& f) {
  const int n = 200000;
  double sum = 0.0;
  for (int m = 0; m < n; ++m) {
    const double b = std::sqrt((m + 0.5) / n);
    const double i = std::asin(b), r = std::asin(b / eta);
    const double reflectance = test::fresnelSineTangent(i, eta);
    sum += reflectance * f(std::cos(M_PI - 2 * i));
    double power = (1 - reflectance) * (1 - reflectance);
    for (int k = 0; k <= maxInteractions - 2 && power > 1e-12; ++k) {
      sum += power * f(std::cos(2 * (i - r) + k * (M_PI - 2 * r)));
      power *= reflectance;
    }
  }
  return sum / n;
}

TraceSettings withSamples(int samples) {
  TraceSettings settings;
  settings.samples = samples;
  return settings;
}

const Vec kPlainView = unit({0.37, -0.52, 0.77});

// Each channel a different linear gradient, so swapping axes or looking back along -view shows.
EquirectMap gradientMap(int width, int height) {
  return test::equirectOf(width, height, [](const Vec& d) {
    return Vec{1 + 0.5 * d[1], 1 + 0.5 * d[0], 1 + 0.5 * d[2]};
  });
}

// L = ((1 - w . view) / 2)^2: lights the hemisphere facing the camera, smoothly (a hard edge
// would be blurred by the bilinear lookup by an amount hard to bound). On a 1024 x 512 map its
// bilinear error is below f'' dtheta^2 / 8 ~ 4e-6 per lookup; the seed-to-seed spread of the
// traces below, at 262144 samples, is below 3e-7 (measured). Hence a tolerance of 5e-6.
double backward(double cosine) {
  return 0.25 * (1 - cosine) * (1 - cosine);
}

}  // namespace

TEST(DropTrace, WhiteFurnaceKeepsAllThePower) {
  // Every interface splits power into R + T = 1, so in a uniform environment all of it comes back;
  // only what is left inside when a path ends (< minPower = 1e-7) is lost.
  const EquirectMap environment = uniformEquirect(64, 32, {1.0f, 2.0f, 3.0f});
  const std::array<Vec, 4> etas = {Vec{1.333, 1.333, 1.333}, Vec{1.0001, 1.0001, 1.0001},
                                   Vec{2.5, 2.5, 2.5}, Vec{1.0001, 1.333, 2.5}};
  for (const Vec& view : {Vec{0, 1, 0}, Vec{0, -1, 0}, Vec{0, 0, -1}, kPlainView}) {
    for (const Vec& eta : etas) {
      const Vec result = traceDropRadiance(environment, view, eta, withSamples(4096));
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(result[c], c + 1.0, 1e-4 * (c + 1.0))
            << "view " << view[0] << "," << view[1] << "," << view[2] << " eta " << eta[c];
      }
    }
  }
}

TEST(DropTrace, NearlyUnitIndexShowsTheEnvironmentBehind) {
  const EquirectMap environment = gradientMap(1024, 512);
  const double eta = 1.0001;
  // Bound on |result - L(view)|. Reflection: only the reflected power (3e-5 of the total: R is
  // ~1e-9 but at grazing incidence) sees other radiance, at most 1 away in these gradients.
  // Refraction deviates rays by D < 2 sqrt(2 (eta - 1)) ~ 0.03 rad; the first-order change of L
  // cancels around the disc up to sampling noise (seed-to-seed < 5e-7), the second order
  // averages 0.5 * mean(1 - cos D) ~ 1e-7. 1e-5 covers those two with margin.
  const double reflectedFraction = deviationQuadrature(eta, 1, [](double) { return 1.0; });
  ASSERT_LT(reflectedFraction, 1e-4);
  const double tolerance = reflectedFraction * 1.0 + 1e-5;
  for (const Vec& view : {Vec{0, 0, -1}, unit({0.3, 0.5, -0.8}), unit({-0.6, -0.3, 0.2})}) {
    const Vec result = traceDropRadiance(environment, view, {eta, eta, eta}, withSamples(65536));
    const auto behind = sampleEquirect(environment, float(view[0]), float(view[1]), float(view[2]));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(result[c], behind[c], tolerance) << "channel " << c;
  }
}

TEST(DropTrace, ExternalReflectionMatchesFresnelQuadrature) {
  // maxInteractions = 1 keeps only the reflection at the first interface, deviated by pi - 2i.
  TraceSettings settings = withSamples(262144);
  settings.maxInteractions = 1;
  for (const Vec& view : {Vec{0, 0, -1}, kPlainView}) {
    const EquirectMap environment = mapAroundView(view, backward);
    for (double eta : {1.333, 2.5}) {
      const double expected = deviationQuadrature(eta, 1, backward);  // 0.0081, 0.063
      const Vec result = traceDropRadiance(environment, view, {eta, eta, eta}, settings);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(result[c], expected, 5e-6) << "eta " << eta;
    }
  }
}

TEST(DropTrace, EveryOrderMatchesTheDeviationSeries) {
  // Truncated after the direct transmission (2 interfaces), after the first internal reflection
  // (3), and complete (the default 2000, where minPower ends the paths).
  for (const Vec& view : {Vec{0, -1, 0}, kPlainView}) {
    const EquirectMap environment = mapAroundView(view, backward);
    for (double eta : {1.333, 2.5}) {
      for (int maxInteractions : {2, 3, 2000}) {
        TraceSettings settings = withSamples(262144);
        settings.maxInteractions = maxInteractions;
        const double expected = deviationQuadrature(eta, maxInteractions, backward);
        const Vec result = traceDropRadiance(environment, view, {eta, eta, eta}, settings);
        EXPECT_NEAR(result[0], expected, 5e-6) << "eta " << eta << " up to " << maxInteractions;
      }
    }
  }
}

TEST(DropTrace, RainbowMatchesTheDeviationSeries) {
  // A band of light 5 degrees wide around 138 degrees from the view direction: the primary bow,
  // one internal reflection (without it the expectation drops from ~0.02 to ~0.001). Per channel
  // a different index, so each channel is checked against its own series (they differ by 2e-3).
  // The bilinear lookup of the narrow band biases the trace by about -8e-6 (it is the same for
  // every seed; the spread across seeds is < 3e-6), hence a tolerance of 3e-5.
  const double bow = 138.0 * M_PI / 180, width = 5.0 * M_PI / 180;
  const auto band = [&](double c) {
    return std::exp(-std::pow((std::acos(std::clamp(c, -1.0, 1.0)) - bow) / width, 2));
  };
  const Vec eta = {1.331, 1.336, 1.343};
  for (const Vec& view : {Vec{0, 1, 0}, kPlainView}) {
    const EquirectMap environment = mapAroundView(view, band);
    const Vec result = traceDropRadiance(environment, view, eta, withSamples(262144));
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(result[c], deviationQuadrature(eta[c], 2000, band), 3e-5) << "channel " << c;
    }
  }
}

TEST(DropTrace, SeedMakesItReproducibleAndMovesItOnlyByTheNoise) {
  const EquirectMap environment = gradientMap(256, 128);
  TraceSettings settings = withSamples(4096);
  const Vec eta = {1.333, 1.333, 1.333};
  const Vec first = traceDropRadiance(environment, kPlainView, eta, settings);
  EXPECT_EQ(traceDropRadiance(environment, kPlainView, eta, settings), first);
  settings.seed = 12345;
  const Vec other = traceDropRadiance(environment, kPlainView, eta, settings);
  // Across seeds the results spread by about 1e-4 at 4096 samples (measured).
  for (int c = 0; c < 3; ++c) {
    EXPECT_NE(other[c], first[c]);
    EXPECT_NEAR(other[c], first[c], 1e-3);
  }
}

TEST(DropTrace, EachChannelIsTracedWithItsOwnIndex) {
  const EquirectMap environment = gradientMap(256, 128);
  const TraceSettings settings = withSamples(1024);
  const Vec eta = {1.331, 1.336, 1.343};
  const Vec dispersive = traceDropRadiance(environment, kPlainView, eta, settings);
  for (int c = 0; c < 3; ++c) {
    const Vec single =
        traceDropRadiance(environment, kPlainView, {eta[c], eta[c], eta[c]}, settings);
    EXPECT_DOUBLE_EQ(dispersive[c], single[c]) << "channel " << c;
  }
}

TEST(DropTrace, ViewDirectionIsNormalised) {
  const EquirectMap environment = gradientMap(256, 128);
  const TraceSettings settings = withSamples(1024);
  const Vec eta = {1.333, 1.333, 1.333};
  const Vec unitResult = traceDropRadiance(environment, kPlainView, eta, settings);
  const Vec scaled = {7 * kPlainView[0], 7 * kPlainView[1], 7 * kPlainView[2]};
  const Vec scaledResult = traceDropRadiance(environment, scaled, eta, settings);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(scaledResult[c], unitResult[c], 1e-12);
}

TEST(DropTrace, RejectsBadInput) {
  const EquirectMap environment = uniformEquirect(8, 4, {1.0f, 1.0f, 1.0f});
  const Vec view = {0, 0, -1}, eta = {1.333, 1.333, 1.333};
  const TraceSettings settings = withSamples(16);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(traceDropRadiance(environment, {nan, 0, -1}, eta, settings), std::invalid_argument);
  EXPECT_THROW(traceDropRadiance(environment, {inf, 0, -1}, eta, settings), std::invalid_argument);
  EXPECT_THROW(traceDropRadiance(environment, {0, 0, 0}, eta, settings), std::invalid_argument);
  EXPECT_THROW(traceDropRadiance(environment, view, {0.5, 0.5, 0.5}, settings),
               std::invalid_argument);
  EXPECT_THROW(traceDropRadiance(environment, view, {1.333, 1.0, 1.333}, settings),
               std::invalid_argument);
  EXPECT_THROW(traceDropRadiance(environment, view, {1.333, 1.333, 3.5}, settings),
               std::invalid_argument);
  EXPECT_THROW(traceDropRadiance(environment, view, {1.333, nan, 1.333}, settings),
               std::invalid_argument);
  EXPECT_THROW(traceDropRadiance(EquirectMap(), view, eta, settings), std::invalid_argument);
  EXPECT_THROW(traceDropRadiance(environment, view, eta, withSamples(0)), std::invalid_argument);
  EXPECT_NO_THROW(traceDropRadiance(environment, view, {1.0001, 1.333, 3.0}, settings));
}

TEST(DropTrace, StaysFiniteAtThePolesBesideABrightTexel) {
  EquirectMap environment(64, 32);
  for (int c = 0; c < 3; ++c) environment.texel(17, 9)[c] = 1e6f;
  const Vec towardTexel = equirectTexelDirection(64, 32, 17, 9);
  const std::array<Vec, 3> etas = {Vec{1.0001, 1.0001, 1.0001}, Vec{2.5, 2.5, 2.5},
                                   Vec{1.0001, 1.333, 2.5}};
  for (const Vec& view : {Vec{0, 1, 0}, Vec{0, -1, 0}, towardTexel}) {
    for (const Vec& eta : etas) {
      const Vec result = traceDropRadiance(environment, view, eta, withSamples(4096));
      for (int c = 0; c < 3; ++c) {
        EXPECT_TRUE(std::isfinite(result[c])) << "eta " << eta[c];
        EXPECT_GE(result[c], 0.0);
        EXPECT_LE(result[c], 1e6 * (1 + 1e-9));  // an average of at most the brightest radiance
      }
    }
  }
}
