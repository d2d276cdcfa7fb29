#pragma once
// The rainbows of falling rain: the light of a sun scattered back by the drops' terms with one
// (primary) and two (secondary) internal reflections, terms n = 3 and 4 of D(theta)
// (drop_transfer.h), per channel with the channel's refractive index (dispersion).
//
// Descartes: a ray with k internal reflections leaves at deviation
//   Dev(gamma) = k pi + 2 gamma - 2 (k + 1) beta,   sin(beta) = sin(gamma) / eta,
// stationary (the caustic: the bow) where cos^2(gamma) = (eta^2 - 1) / (k^2 + 2k). The
// scattering angle (from the light's direction of travel) is Dev folded into [0, 180] deg:
// about 138 deg for the primary (42 deg from the antisolar point), 129 deg for the secondary
// (51 deg), red outside the primary and inside the secondary.
//
// The bow's profile: the power of terms 3 and 4 binned in theta (finite bin averages instead of
// the caustic's integrable infinity), then smoothed by the sun's disc and by the width of the
// Airy peak of drops of the given diameter, ~ (lambda / d)^(2/3) rad (van de Hulst, Airy theory):
// big drops give narrow, saturated bows; small drops broad, pale ones.
#include <array>
#include <vector>

namespace pluvia::optics {

// Scattering angle of the Descartes (minimum deviation) ray with k internal reflections, degrees.
double descartesScatteringDeg(int internalReflections, double eta);

struct RainbowProfileSettings {
  double sunRadiusDeg = 0.27;   // angular radius of the sun's disc
  double dropDiameterMm = 1.5;  // sets the Airy width; 0: geometric optics only
  double binDeg = 0.05;         // bins in theta
  int discSamples = 200000;     // rays per term, uniform in b^2 over the drop's disc
};

// D of terms 3 and 4 alone, per steradian, in bins of theta (degrees) for one refractive index.
struct RainbowProfile {
  double binDeg = 0.05;
  std::vector<double> density;  // bin k: theta in [k, k + 1] * binDeg
  // Linear interpolation between bin centres, theta in degrees.
  double at(double thetaDeg) const;
};
RainbowProfile rainbowProfile(double eta, const RainbowProfileSettings& settings = {});

// The three channels' profiles (R, G, B with eta[c]).
std::array<RainbowProfile, 3> rainbowProfiles(const std::array<double, 3>& eta,
                                              const RainbowProfileSettings& settings = {});

}  // namespace pluvia::optics
