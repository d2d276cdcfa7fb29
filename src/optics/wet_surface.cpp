#include "optics/wet_surface.h"

#include <algorithm>
#include <cmath>

#include "optics/fresnel.h"

namespace pluvia::optics {

double diffuseFresnelReflectance(double eta) {
  // Midpoint rule in mu = cos(theta): Rbar = 2 int_0^1 R(mu) mu dmu; R is smooth but steep near
  // mu = 0, where 4096 steps leave an error under 1e-7.
  constexpr int kSteps = 4096;
  double sum = 0.0;
  for (int i = 0; i < kSteps; ++i) {
    const double mu = (i + 0.5) / kSteps;
    sum += fresnelReflectance(mu, eta) * mu;
  }
  return 2.0 * sum / kSteps;
}

WetFilm wetFilm(double eta) {
  WetFilm film;
  film.eta = eta;
  film.externalDiffuse = diffuseFresnelReflectance(eta);
  film.internalDiffuse = 1.0 - (1.0 - film.externalDiffuse) / (eta * eta);
  return film;
}

double wetAlbedo(const WetFilm& film, double albedo) {
  const double a = std::clamp(albedo, 0.0, 1.0), p = film.internalDiffuse;
  return (1.0 - film.externalDiffuse) * (1.0 - p) * a / (1.0 - p * a);
}

double wetRadianceRatio(const WetFilm& film, double albedo, double cosView) {
  return wetRadianceRatioAt(film, albedo,
                            fresnelReflectance(std::clamp(cosView, 0.0, 1.0), film.eta));
}

double wetRadianceRatioAt(const WetFilm& film, double albedo, double viewReflectance) {
  const double a = std::clamp(albedo, 0.0, 1.0);
  return (1.0 - film.externalDiffuse) * (1.0 - viewReflectance) /
         (film.eta * film.eta * (1.0 - film.internalDiffuse * a));
}

}  // namespace pluvia::optics
