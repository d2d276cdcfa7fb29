// Lekner and Dorf's wet surface (optics/wet_surface.h) against independent integrals: the diffuse
// reflectance from outside against the reflectance of a level sea under a uniform sky (0.066,
// the value ocean optics quotes for n = 1.33), the internal one (p) as
// Fresnel's reflectance from inside (total internal reflection included) integrated over the
// hemisphere, and the wet albedo as the hemisphere's mean of the radiance ratio.
#include <gtest/gtest.h>

#include <cmath>

#include "optics/fresnel.h"
#include "optics/wet_surface.h"

using namespace pluvia::optics;

namespace {

// 2 int_0^1 f(mu) mu dmu by Simpson's rule on 20000 intervals.
template <class F>
double cosineMean(F f) {
  constexpr int kIntervals = 20000;
  double sum = 0.0;
  for (int i = 0; i <= kIntervals; ++i) {
    const double mu = double(i) / kIntervals;
    const double weight = i == 0 || i == kIntervals ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += weight * f(mu) * mu;
  }
  return 2.0 * sum / (3.0 * kIntervals);
}

}  // namespace

TEST(WetSurface, DiffuseReflectanceOfWaterIsALevelSeaUnderAUniformSkys) {
  EXPECT_NEAR(diffuseFresnelReflectance(1.333), 0.066, 0.001);
  EXPECT_NEAR(diffuseFresnelReflectance(1.0), 0.0, 1e-12);
}

TEST(WetSurface, InternalReflectanceIsFresnelsFromInsideOverTheHemisphere) {
  for (const double eta : {1.2, 1.333, 1.5}) {
    const WetFilm film = wetFilm(eta);
    // From inside, a diffuse field meets the interface at every angle; beyond the critical one
    // it is reflected whole. Per unit solid angle inside, the cosine-weighted mean is p.
    const double inside = cosineMean([&](double mu) { return fresnelReflectance(mu, 1.0 / eta); });
    EXPECT_NEAR(film.internalDiffuse, inside, 2e-4) << "eta " << eta;
  }
}

TEST(WetSurface, WetAlbedoIsTheMeanRadianceRatioAndDarkerTheDarkerTheSurface) {
  const WetFilm film = wetFilm(1.333);
  double previousShare = 1.0;
  for (const double a : {0.9, 0.5, 0.3, 0.1, 0.02}) {
    const double mean = cosineMean([&](double mu) { return wetRadianceRatio(film, a, mu); });
    EXPECT_NEAR(wetAlbedo(film, a), a * mean, 1e-4 * a) << "albedo " << a;
    const double share = wetAlbedo(film, a) / a;
    EXPECT_LT(share, previousShare) << "darker when wet, more so for a darker surface: " << a;
    previousShare = share;
  }
  // A black surface under water keeps (1 - Rbar)(1 - p) of its (vanishing) albedo: about half.
  EXPECT_NEAR(wetAlbedo(film, 1e-6) / 1e-6, 0.49, 0.01);
  // Seen head on the ratio exceeds the mean; at grazing angles nothing leaves the film.
  EXPECT_GT(wetRadianceRatio(film, 0.3, 1.0), wetAlbedo(film, 0.3) / 0.3);
  EXPECT_NEAR(wetRadianceRatio(film, 0.3, 0.0), 0.0, 1e-12);
}
