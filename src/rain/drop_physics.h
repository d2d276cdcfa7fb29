#pragma once
// Rain drop physics: sizes from the rain rate and fall speeds from the size.
//  - Marshall–Palmer (1948) size distribution N(D) = N0 exp(-Lambda D), N0 = 8000 m^-3 mm^-1,
//    Lambda = 4.1 R^-0.21 mm^-1 with R the rain rate in mm/h (Garg and Nayar, section 3).
//  - Terminal velocity of Atlas, Srivastava and Sekhon (1973): v = 9.65 - 10.3 exp(-0.6 D) m/s,
//    D in mm, clamped at 0 for tiny drops where the fit goes negative.
//  - Gamma size distribution N(D) = N0 D^mu exp(-Lambda D) (Ulbrich 1983), the other family
//    Garg and Nayar name, with fewer tiny drops than Marshall–Palmer.
//  - Gunn and Kinzer (1949) measured terminal velocities, interpolated linearly.
namespace pluvia::rain {

inline constexpr double kMarshallPalmerN0 = 8000.0;  // m^-3 mm^-1

// Lambda in 1/mm; rate must be > 0.
double marshallPalmerSlopePerMm(double rainRateMmPerHour);

// Drops per cubic metre with diameter in [minDiameterMm, maxDiameterMm]; 0 for a rate of 0.
double dropsPerCubicMeter(double rainRateMmPerHour, double minDiameterMm, double maxDiameterMm);

// Inverse-CDF sample of the truncated exponential distribution on [min, max] for u in [0, 1).
double sampleDiameterMm(double u, double rainRateMmPerHour, double minDiameterMm,
                        double maxDiameterMm);

double terminalVelocityMetersPerSecond(double diameterMm);

enum class SizeDistribution { MarshallPalmer, Gamma };

// Gamma parameters at a rain rate: mu = 2, with the same liquid water content and median volume
// diameter D0 as Marshall–Palmer at that rate (Ulbrich's relation D0 Lambda = 3.67 + mu). Both
// families then carry the same water and nearly the same rain rate (the fall-speed weighting
// differs slightly), so switching the family changes the shape of the spectrum, not the
// amount of rain. Rate must be > 0.
struct GammaParameters {
  double n0;  // m^-3 mm^-(1 + mu)
  double mu;
  double slopePerMm;  // Lambda
};
GammaParameters gammaParameters(double rainRateMmPerHour);

// As the Marshall–Palmer functions above, for either family: drops per cubic metre with diameter
// in [min, max] (0 for a rate of 0) and the inverse-CDF sample of the truncated distribution.
double dropsPerCubicMeter(SizeDistribution distribution, double rainRateMmPerHour,
                          double minDiameterMm, double maxDiameterMm);
double sampleDiameterMm(SizeDistribution distribution, double u, double rainRateMmPerHour,
                        double minDiameterMm, double maxDiameterMm);

// Gunn and Kinzer (1949) table, 0.1 to 5.8 mm, linear between entries; Stokes (v ~ D^2) below
// 0.1 mm, and 9.17 m/s above 5.8 mm, where drops break up.
double gunnKinzerVelocityMetersPerSecond(double diameterMm);

enum class VelocityModel { Atlas, GunnKinzer };
double terminalVelocity(VelocityModel model, double diameterMm);  // m/s

// Extinction of visible light by Marshall–Palmer rain, 1/m: every drop removes twice its
// geometric cross-section (extinction efficiency 2, drops far larger than the wavelength), so
// sigma = 2 * integral of N(D) pi D^2 / 4 dD = pi N0 / Lambda^3 = 0.365 R^0.63 per km.
// 0 for a rate of 0.
double rainExtinctionPerMeter(double rainRateMmPerHour);

// Meteorological visibility through that rain (Koschmieder: the distance at which a black
// object's contrast falls to 2 %, 3.912 / sigma), in metres; +inf for a rate of 0. About 2 km at
// 15 mm/h and 590 m at 100 mm/h.
double rainVisibilityMeters(double rainRateMmPerHour);

// Frequency of a drop's oblate-prolate oscillation, mode (2, 0), in Hz (Garg and Nayar 2006,
// Eq. 2, after Rayleigh): omega_n = sqrt(n (n - 1) (n + 2) sigma / (rho r0^3)) with r0 the
// undistorted radius, sigma = 0.0728 N/m, rho = 1000 kg/m^3; f = omega_2 / (2 pi). About 60 Hz
// (a 1/60 s period) at r0 = 1.6 mm, and f ~ r0^-3/2. The transverse mode (3, 1) runs at
// sqrt(30 / 8) = 1.94 times this.
double oscillationFrequencyHz(double diameterMm);

}  // namespace pluvia::rain
