#pragma once
// Unpolarised Fresnel reflectance from air into index eta at incidence angle `incidence`, in the
// sine and tangent form: written apart from src/optics (which uses the cosine form) so optics
// tests compare against an independent formula.
#include <cmath>

namespace pluvia::test {

inline double fresnelSineTangent(double incidence, double eta) {
  if (incidence < 1e-8) return std::pow((eta - 1.0) / (eta + 1.0), 2.0);
  const double refraction = std::asin(std::sin(incidence) / eta);
  const double rs = std::sin(incidence - refraction) / std::sin(incidence + refraction);
  const double rp = std::tan(incidence - refraction) / std::tan(incidence + refraction);
  return 0.5 * (rs * rs + rp * rp);
}

}  // namespace pluvia::test
