#pragma once
// The ground the rain falls on, wet (optics/wet_surface.h): where the frame's depth shows a
// surface facing up, the plate's own radiance is what the dry surface sends back, so its albedo
// is a = pi L / E per channel (E: the luminance of the environment's irradiance on level ground,
// the light taken as white as the camera balanced it), and under the
// film it becomes L' = L ratio(a, theta) + R(theta) G(r): the darkening of Lekner and Dorf and
// the film's gloss, G the environment (blurred, a rough film) along the view ray mirrored in the
// level film, R(theta) Fresnel's reflectance at the viewing angle. Distant ground, seen at grazing
// angles, darkens most and mirrors most of the sky, as a wet road does.
//
// Only a surface that holds a film mirrors: paving and asphalt do, grass and soil soak the water
// in and only darken. Which one a pixel shows is not known; its colour stands in for it (a
// proxy, a look rather than physics): the gloss is weighted by filmCoverage of the mean colour
// over 15 x 15 px around the pixel (a material is a region's), 1 for grey, falling to 0 at
// kSoakingSaturation (grass, earth and brick are more saturated than that; road surfaces less).
#include <array>
#include <vector>

#include "geometry/camera.h"
#include "image/equirect.h"
#include "image/image.h"

namespace pluvia::rain {

// How much of each pixel is ground the rain wets: 1 where the surface the depth shows (z-depth,
// metres, +inf the sky) faces up within `fullTiltDeg` of level on the camera's side, falling
// linearly in cos(tilt) to 0 at fullTiltDeg + fadeDeg (no seam where a guessed ground bends); 0
// for the sky, for surfaces facing down, and where no neighbour continues the surface (more than
// 25 % apart in depth, and 1 / z not running straight through the three).
std::vector<float> wetGroundWeights(const Camera& camera, const std::vector<float>& depth,
                                    double fullTiltDeg, double fadeDeg);

// Irradiance on level ground (normal +Y) from the map's upper hemisphere, per channel (pi for a
// map of radiance 1).
std::array<double, 3> levelIrradiance(const EquirectMap& environment);

inline constexpr double kSoakingSaturation = 0.3;

// The share of a pixel (linear RGB) under a mirroring film: 1 - saturation / kSoakingSaturation,
// clamped to [0, 1], saturation = (max - min) / max.
double filmCoverage(const float* rgb);

struct WetGroundLight {
  EquirectMap gloss;                   // what the film mirrors (the environment, blurred)
  std::array<double, 3> irradiance{};  // levelIrradiance of the environment
};

// What the level film (index `eta`) shows along each pixel's view ray where weights[i] > 0:
// Fresnel's reflectance there and the environment it mirrors (light.gloss), made once per camera.
struct LevelFilmView {
  std::vector<float> reflectance;              // per pixel; 0 where the weight is
  std::vector<std::array<float, 3>> mirrored;  // per pixel
};
LevelFilmView levelFilmView(const Camera& camera, const std::vector<float>& weights,
                            const WetGroundLight& light, double eta);

// Wets `image` (RGB; alpha kept) by weight `wetness` * weights[i] (0..1 per pixel), the film's
// mirror weighted by `gloss` (0..1; 0: the darkening alone); `view`: levelFilmView of the same
// camera, weights, light and eta.
void wetGround(Image& image, const std::vector<float>& weights, const LevelFilmView& view,
               double wetness, double gloss, const WetGroundLight& light, double eta);

}  // namespace pluvia::rain
