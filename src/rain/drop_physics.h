#pragma once
// Rain drop physics: sizes from the rain rate and fall speeds from the size.
//  - Marshall–Palmer (1948) size distribution N(D) = N0 exp(-Lambda D), N0 = 8000 m^-3 mm^-1,
//    Lambda = 4.1 R^-0.21 mm^-1 with R the rain rate in mm/h (Garg and Nayar, section 3).
//  - Terminal velocity of Atlas, Srivastava and Sekhon (1973): v = 9.65 - 10.3 exp(-0.6 D) m/s,
//    D in mm, clamped at 0 for tiny drops where the fit goes negative.
namespace pluvia::rain {

inline constexpr double kMarshallPalmerN0 = 8000.0;  // m^-3 mm^-1

// Lambda in 1/mm; rate must be > 0.
double marshallPalmerSlopePerMm(double rainRateMmPerHour);

// Drops per cubic metre with diameter in [minDiameterMm, maxDiameterMm]; 0 for a rate of 0.
double dropsPerCubicMeter(double rainRateMmPerHour, double minDiameterMm, double maxDiameterMm);

// Inverse-CDF sample of the truncated exponential distribution on [min, max] for u in [0, 1).
double sampleDiameterMm(double u, double rainRateMmPerHour, double minDiameterMm, double maxDiameterMm);

double terminalVelocityMetersPerSecond(double diameterMm);

}  // namespace pluvia::rain
