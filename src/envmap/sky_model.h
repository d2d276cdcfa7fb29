#pragma once
// Analytic skies for the part of the sphere a pan never saw: the Preetham clear sky (turbidity
// and sun direction), the CIE overcast sky and a uniform one, each fitted to seen sky radiance
// with a free scale per channel; the fit with the smallest residual is kept.
// Directions are world unit vectors with +Y up (image/equirect.h).
#include <array>
#include <optional>
#include <string>
#include <vector>

namespace pluvia::envmap {

using Vec3 = std::array<double, 3>;

// Preetham, Shirley and Smits 1999, "A Practical Analytic Model for Daylight" (SIGGRAPH),
// appendix A.2: the Perez distribution F(theta, gamma) for Y, x and y with coefficients linear
// in the turbidity, and the zenith luminance (kcd/m^2) and chromaticity.
struct PerezCoefficients {
  double a, b, c, d, e;
};
PerezCoefficients preethamLuminanceCoefficients(double turbidity);
PerezCoefficients preethamXCoefficients(double turbidity);
PerezCoefficients preethamYCoefficients(double turbidity);
// F(theta, gamma) = (1 + A exp(B / cos theta)) (1 + C exp(D gamma) + E cos^2 gamma); theta the
// view's zenith angle, gamma its angle to the sun (radians).
double perez(const PerezCoefficients& k, double theta, double gamma);
// Zenith luminance in kcd/m^2: (4.0453 T - 4.9710) tan chi - 0.2155 T + 2.4192 with
// chi = (4/9 - T/120)(pi - 2 theta_s).
double preethamZenithLuminance(double turbidity, double sunZenith);
// Zenith chromaticity (x, y): [T^2 T 1] M [theta_s^3 theta_s^2 theta_s 1]^T.
std::array<double, 2> preethamZenithChromaticity(double turbidity, double sunZenith);
// Absolute sky radiance along `view` as linear Rec.709 RGB (from CIE xyY, Y in kcd/m^2),
// for a view above the horizon; the view's zenith angle is clamped just below 90 degrees.
Vec3 preethamRgb(double turbidity, const Vec3& sun, const Vec3& view);

// CIE overcast (Moon and Spencer 1942, CIE standard sky 1): L = Lz (1 + 2 cos theta) / 3.
double cieOvercastShape(const Vec3& view);

// Seen sky radiance to fit: a direction above the horizon, its RGB (linear, any scale), a weight
// (solid angle).
struct SkySample {
  Vec3 direction;
  std::array<float, 3> rgb;
  double weight = 1.0;
};

enum class SkyKind { Preetham, CieOvercast, Uniform };

struct SkyFit {
  SkyKind kind = SkyKind::Uniform;
  double turbidity = 0.0;         // Preetham
  bool grey = false;              // Preetham: its luminance distribution only, in one colour
  Vec3 sun{0, 1, 0};              // Preetham
  std::array<double, 3> scale{};  // per channel, on the model's shape
  double residual = 0.0;          // weighted RMS of log(seen / model), mean over channels
  std::string describe() const;   // "preetham T 3.2, sun at 20° elevation 35° azimuth", ...
};

struct SkyFitSettings {
  // The sun when it is known (a light given by the user, or the clipped disc in the footage):
  // the Preetham fit then searches the turbidity only.
  std::optional<Vec3> sun;
  bool preetham = true;  // false: CIE overcast and uniform only
};

// Fits each model by least squares on log radiance (so the dim zenith and the bright
// circumsolar sky weigh alike; the per-channel scale is then the weighted mean log ratio):
// Preetham over turbidity 1.7..10 and the sun (a coarse grid over the upper hemisphere refined
// around the best, unless given), CIE overcast and uniform in closed form. Returns the fit with
// the smallest residual; nullopt with no usable sample.
std::optional<SkyFit> fitSky(const std::vector<SkySample>& samples, const SkyFitSettings& settings);

// The fitted sky's radiance along `view` (above the horizon; below it, its value at the horizon).
std::array<double, 3> evaluateSky(const SkyFit& fit, const Vec3& view);

// Irradiance on a horizontal surface under the fitted sky (pi for a uniform sky of radiance 1),
// integrated numerically over the upper hemisphere; the sun's disc is not in the model.
std::array<double, 3> skyIrradiance(const SkyFit& fit);

}  // namespace pluvia::envmap
