#include "optics/local_light.h"

#include <algorithm>

namespace pluvia::optics {

double spotFactor(const LocalLight& light, double cosTheta) {
  if (!light.spot) return 1.0;
  if (cosTheta < light.cosHalfAngle) return 0.0;
  const double span = 1.0 - light.cosHalfAngle;
  // A cone of A -> 0: only its axis is lit, at full intensity.
  const double t = span > 1e-12 ? std::min(1.0, (cosTheta - light.cosHalfAngle) / span) : 1.0;
  return (1.0 - light.falloffQ) * t + light.falloffQ;
}

}  // namespace pluvia::optics
