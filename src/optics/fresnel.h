#pragma once
// Unpolarised Fresnel reflectance at a smooth interface (Wang et al. 2006, Appendix A).
namespace pluvia::optics {

// Reflectance R for light arriving at angle theta_i (cosIncident = cos theta_i, in [0, 1]) on an
// interface with relative index rho = eta_t / eta_i. Computed as (Rs + Rp) / 2, the same value as
// the paper's form in rho and m = cos theta_t / cos theta_i, but finite at grazing incidence
// (cos theta_i -> 0 gives R -> 1, where m diverges). Total internal reflection gives 1.
double fresnelReflectance(double cosIncident, double rho);

// The paper's own expression, for the test that the two agree: R = ((1 - rho^2)^2 m^2 +
// (1 - m^2)^2 rho^2) / (m (1 + rho^2) + rho (1 + m^2))^2. Not finite at cos theta_i = 0.
double fresnelReflectancePaperForm(double cosIncident, double rho);

}  // namespace pluvia::optics
