// The analytic skies of the unseen-sphere fill (envmap/sky_model.h): Preetham's formulas
// against values worked by hand from the paper's appendix, the clear sky's known shape, and the
// fit recovering turbidity and sun from a band of sky a pan sees.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "envmap/sky_model.h"

namespace pluvia::envmap {
namespace {

constexpr double kDeg = M_PI / 180.0;

Vec3 direction(double elevationDeg, double azimuthDeg) {
  const double e = elevationDeg * kDeg, a = azimuthDeg * kDeg;
  return {std::cos(e) * std::sin(a), std::sin(e), -std::cos(e) * std::cos(a)};
}

double angleDeg(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a[0] * b[0] + a[1] * b[1] + a[2] * b[2], -1.0, 1.0)) / kDeg;
}

double luminance(const Vec3& rgb) {
  return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
}

TEST(SkyModel, PreethamZenithValuesMatchTheAppendixWorkedByHand) {
  // T = 2, sun 30° from the zenith: chi = (4/9 - 2/120)(pi - pi/3) = 0.895936,
  // tan chi = 1.249693, Yz = (8.0906 - 4.9710) 1.249693 - 0.4310 + 2.4192 = 5.886743 kcd/m^2.
  EXPECT_NEAR(preethamZenithLuminance(2.0, 30.0 * kDeg), 5.886743, 1e-4);
  // Sun at the zenith (theta_s = 0): only the last column of the chromaticity matrices counts:
  // x = 2 (0.00394) + 0.25886 = 0.26674, y = 2 (0.00516) + 0.26688 = 0.27720.
  const auto xy = preethamZenithChromaticity(2.0, 0.0);
  EXPECT_NEAR(xy[0], 0.26674, 1e-5);
  EXPECT_NEAR(xy[1], 0.27720, 1e-5);
  // The RGB model at the zenith carries the zenith luminance (Rec.709 Y weights).
  const Vec3 sun = direction(60.0, 0.0);
  EXPECT_NEAR(luminance(preethamRgb(2.0, sun, {0, 1, 0})), 5.886743, 5.886743 * 1e-3);
  // Perez F at theta = 0 and gamma = theta_s is the normaliser: 1 by construction there.
  const auto k = preethamLuminanceCoefficients(3.0);
  EXPECT_NEAR(perez(k, 0.0, 0.5),
              (1 + k.a * std::exp(k.b)) *
                  (1 + k.c * std::exp(k.d * 0.5) + k.e * std::cos(0.5) * std::cos(0.5)),
              1e-12);
}

TEST(SkyModel, PreethamClearSkyHasItsKnownShape) {
  // A clear sky (T = 2.5, sun 30° up): brightest round the sun, darkest about 90° from it in the
  // sun's vertical plane, brighter towards the horizon than at that minimum, and the zenith
  // bluer than D65 white (x < 0.3127).
  const Vec3 sun = direction(30.0, 0.0);
  const double t = 2.5;
  const double nearSun = luminance(preethamRgb(t, sun, direction(35.0, 0.0)));
  double darkest = 1e30, darkestAt = 0.0;
  for (double e = 1.0; e <= 179.0; e += 1.0) {  // up through the zenith and down the far side
    const Vec3 v = e <= 90 ? direction(e, 180.0) : direction(180.0 - e, 0.0);
    const double l = luminance(preethamRgb(t, sun, v));
    if (l < darkest) darkest = l, darkestAt = angleDeg(v, sun);
  }
  EXPECT_GT(nearSun / darkest, 5.0);
  EXPECT_NEAR(darkestAt, 90.0, 25.0);
  EXPECT_GT(luminance(preethamRgb(t, sun, direction(3.0, 180.0))), 1.5 * darkest);
  const Vec3 zenith = preethamRgb(t, sun, {0, 1, 0});
  EXPECT_GT(zenith[2], zenith[0]);  // blue over red
  EXPECT_LT(preethamZenithChromaticity(t, 60.0 * kDeg)[0], 0.3127);
}

// The band a level pan of 60° x 34° frames sees: elevation 0..28°, every azimuth.
std::vector<SkySample> panBand(double t, const Vec3& sun, const std::array<double, 3>& scale,
                               double noise) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, noise);
  std::vector<SkySample> samples;
  for (double e = 1.0; e < 28.0; e += 2.0)
    for (double a = 0.0; a < 360.0; a += 4.0) {
      const Vec3 v = direction(e, a);
      const Vec3 rgb = preethamRgb(t, sun, v);
      SkySample s{v, {}, std::cos(e * kDeg)};
      for (size_t c = 0; c < 3; ++c) s.rgb[c] = float(scale[c] * rgb[c] * std::exp(n(rng)));
      samples.push_back(s);
    }
  return samples;
}

TEST(SkyModel, FitRecoversTurbiditySunAndScaleFromTheSeenBand) {
  const Vec3 sun = direction(22.0, 65.0);
  const std::array<double, 3> scale = {0.011, 0.010, 0.013};    // camera exposure and white balance
  const auto fit = fitSky(panBand(3.0, sun, scale, 0.02), {});  // 2 % noise per texel
  ASSERT_TRUE(fit.has_value());
  ASSERT_EQ(fit->kind, SkyKind::Preetham);
  EXPECT_NEAR(fit->turbidity, 3.0, 0.3);
  EXPECT_LT(angleDeg(fit->sun, sun), 3.0);
  // The zenith the band never saw, within 5 %.
  const auto zenith = evaluateSky(*fit, {0, 1, 0});
  const Vec3 truth = preethamRgb(3.0, sun, {0, 1, 0});
  for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(zenith[c] / (scale[c] * truth[c]), 1.0, 0.05);
}

TEST(SkyModel, FitWithTheSunGivenSearchesTheTurbidityOnly) {
  const Vec3 sun = direction(40.0, -120.0);
  SkyFitSettings settings;
  settings.sun = sun;
  const auto fit = fitSky(panBand(6.0, sun, {1, 1, 1}, 0.0), settings);
  ASSERT_TRUE(fit.has_value());
  ASSERT_EQ(fit->kind, SkyKind::Preetham);
  EXPECT_NEAR(fit->turbidity, 6.0, 0.1);
  EXPECT_LT(angleDeg(fit->sun, sun), 1e-4);  // kept as given (acos rounding)
  EXPECT_LT(fit->residual, 1e-3);
}

TEST(SkyModel, OvercastSkyIsFittedAsOvercastAndUniformAsUniform) {
  std::vector<SkySample> overcast, uniform;
  for (double e = 1.0; e < 60.0; e += 2.0)
    for (double a = 0.0; a < 360.0; a += 10.0) {
      const Vec3 v = direction(e, a);
      const float f = float(0.8 * cieOvercastShape(v));
      overcast.push_back({v, {f, f, f}, 1.0});
      uniform.push_back({v, {0.3f, 0.4f, 0.5f}, 1.0});
    }
  overcast.push_back({direction(30, 0), {NAN, 0.5f, 0.5f}, 1.0});  // left out, not spread
  const auto o = fitSky(overcast, {});
  ASSERT_TRUE(o.has_value());
  EXPECT_EQ(o->kind, SkyKind::CieOvercast);
  EXPECT_NEAR(evaluateSky(*o, {0, 1, 0})[1], 0.8, 1e-3);
  EXPECT_TRUE(std::isfinite(evaluateSky(*o, {0, 1, 0})[0]));
  const auto u = fitSky(uniform, {});
  ASSERT_TRUE(u.has_value());
  EXPECT_EQ(u->kind, SkyKind::Uniform);
  // A uniform sky of radiance L gives irradiance pi L.
  EXPECT_NEAR(skyIrradiance(*u)[2], M_PI * 0.5, 1e-3);
  EXPECT_FALSE(fitSky({}, {}).has_value());
}

}  // namespace
}  // namespace pluvia::envmap
