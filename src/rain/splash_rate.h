#pragma once
// How often drops strike a horizontal surface: the drop flux through it,
//   F = integral_{Dmin}^{Dmax} N(D) v(D) dD     [impacts per m^2 per second],
// N(D) the size distribution (drops per m^3 per mm of diameter, drop_physics.h) and v(D) the
// terminal velocity: drops in a column of height v dt above a square metre all land within dt.
// For Marshall-Palmer and Atlas et al.'s velocity, v = 9.65 - 10.3 exp(-0.6 D) (0 below
// D0 = ln(10.3 / 9.65) / 0.6 = 0.109 mm), the integral is closed:
//   F = N0 [9.65 (e^{-L a} - e^{-L b}) / L - 10.3 (e^{-(L+0.6) a} - e^{-(L+0.6) b}) / (L + 0.6)],
// a = max(Dmin, D0), b = Dmax, L = Lambda; the other pairs are integrated numerically (Simpson).
// The diameters of the drops that land follow N(D) v(D), not N(D): big drops fall faster.
#include <vector>

#include "rain/drop_physics.h"

namespace pluvia::rain {

// N(D), drops per m^3 per mm, at diameter D (mm); 0 for a rate of 0.
double sizeDensityPerMm(SizeDistribution distribution, double rainRateMmPerHour, double diameterMm);

// F above; 0 for a rate of 0.
double impactsPerSquareMeterSecond(SizeDistribution distribution, VelocityModel velocity,
                                   double rainRateMmPerHour, double minDiameterMm,
                                   double maxDiameterMm);

// Diameters of landing drops, by inverse CDF of N(D) v(D) tabulated on [min, max].
class ImpactDiameters {
 public:
  ImpactDiameters(SizeDistribution distribution, VelocityModel velocity, double rainRateMmPerHour,
                  double minDiameterMm, double maxDiameterMm);
  double sampleMm(double u) const;  // u in [0, 1)

 private:
  double minMm_, stepMm_;
  std::vector<double> cdf_;  // at minMm_ + k * stepMm_
};

}  // namespace pluvia::rain
