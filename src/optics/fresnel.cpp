#include "optics/fresnel.h"

#include <algorithm>
#include <cmath>

namespace pluvia::optics {
namespace {

// cos theta_t by Snell's law, or -1 under total internal reflection.
double cosTransmitted(double cosIncident, double rho) {
  const double sin2Incident = std::max(0.0, 1.0 - cosIncident * cosIncident);
  const double sin2Transmitted = sin2Incident / (rho * rho);
  if (sin2Transmitted >= 1.0) return -1.0;
  return std::sqrt(1.0 - sin2Transmitted);
}

}  // namespace

double fresnelReflectance(double cosIncident, double rho) {
  const double ci = std::clamp(cosIncident, 0.0, 1.0);
  const double ct = cosTransmitted(ci, rho);
  if (ct < 0.0) return 1.0;
  const double rs = (ci - rho * ct) / (ci + rho * ct);
  const double rp = (rho * ci - ct) / (rho * ci + ct);
  return 0.5 * (rs * rs + rp * rp);
}

double fresnelReflectancePaperForm(double cosIncident, double rho) {
  const double ct = cosTransmitted(cosIncident, rho);
  if (ct < 0.0) return 1.0;
  const double m = ct / cosIncident;
  const double rho2 = rho * rho, m2 = m * m;
  const double numerator = (1.0 - rho2) * (1.0 - rho2) * m2 + (1.0 - m2) * (1.0 - m2) * rho2;
  const double denominator = m * (1.0 + rho2) + rho * (1.0 + m2);
  return numerator / (denominator * denominator);
}

}  // namespace pluvia::optics
