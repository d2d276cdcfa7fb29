#pragma once
// Splashes where drops strike surfaces that face up. The surfaces come from the frame's depth
// plane: each pixel's footprint (its world point and those of its right and lower neighbours)
// gives its normal and the area it covers projected on the horizontal, so a pixel receives
// F * area impacts per second (F from splash_rate.h). Pixels are grouped in tiles; the impacts
// of each birth frame and tile are drawn from a Poisson law with a generator seeded by (seed,
// frame, tile) alone, so a frame's splashes never depend on the frames rendered before it
// (chunks render identical frames). A splash lives longer than a frame: frame f draws the
// impacts born in the frames before it that are still alive, placed on f's depth (exact for a
// locked-off camera; a moving camera's older splashes ride with the picture).
//
// Each impact of a drop of diameter D at speed U makes (scalings after Yarin 2006, crown
// splashes on wet surfaces; the constants are a look, not a fit):
//  - a crown: a thin sheet of water rising around the impact point, leaning out by
//    kCrownLeanDeg, radius 2 D sqrt(t / tau) to 2 D, height D, over tau = 20 D / U, drawn as
//    kCrownPoints patches that share the sheet's area as the camera sees it (both walls: the
//    sheet is clear). A patch shows what lies behind it and the environment mirrored in its face
//    towards the camera with a thin film's reflectance (crownSheetReflection): the far wall's
//    inner face mirrors the sky (a bright arc), the near wall's outer face the ground;
//  - 2 + 2 D[mm] secondary droplets of diameter 0.15 D, thrown at 0.2 U, 45..75 deg above the
//    surface in random azimuths, falling back under gravity until they reach the surface.
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "rain/splash_rate.h"

namespace pluvia::rain {

inline constexpr double kGravity = 9.81;  // m/s^2
inline constexpr int kCrownPoints = 12;

// Horizontal area (m^2) of each pixel's surface where it faces up (normal within maxTiltDeg of
// +Y), else 0; 0 too at depth discontinuities (more than 25 % between neighbours), sky, and
// depths beyond maxDepthMeters (the level of detail's limit: not looked at, so a far surface
// costs nothing).
std::vector<float> upFacingAreaPerPixel(
    const Camera& camera, const std::vector<float>& depth, double maxTiltDeg,
    double maxDepthMeters = std::numeric_limits<double>::infinity());

struct Impact {
  Eigen::Vector3d point;  // world, on the surface
  double timeSeconds = 0.0;
  double diameterMm = 0.0;
  double speedMetersPerSecond = 0.0;
  uint64_t key = 0;  // seeds the splash's own random choices
};

struct SplashField {
  std::vector<float> depth;         // the frame's z-depth, metres
  std::vector<float> areaPerPixel;  // upFacingAreaPerPixel of that depth
  double impactsPerSquareMeterSecond = 0.0;
  int tilePx = 32;
};

// The field's up-facing area summed per tile (running sums over the tile's pixels, row by row),
// made once per frame and shared by every birth frame alive in it.
struct SplashTiles {
  int tilesX = 0, tilesY = 0;
  std::vector<std::vector<double>> cumulativeArea;  // per tile; empty: no up-facing area
};
SplashTiles splashTiles(const SplashField& field, int width, int height);

// The impacts born during frame `birthFrame` ([birthFrame, birthFrame + 1) / fps), placed on
// `camera`'s view of the field.
std::vector<Impact> impactsBorn(const SplashField& field, const SplashTiles& tiles,
                                const Camera& camera, int64_t birthFrame, double fps, uint64_t seed,
                                const ImpactDiameters& diameters, VelocityModel velocity);
// The same, with the tiles made for this call.
std::vector<Impact> impactsBorn(const SplashField& field, const Camera& camera, int64_t birthFrame,
                                double fps, uint64_t seed, const ImpactDiameters& diameters,
                                VelocityModel velocity);

// Lifetime of an impact's splash: until its last droplet lands.
double splashLifeSeconds(const Impact& impact);

// A particle's motion over the shutter: world positions at its start and end, and diameter.
struct SplashParticle {
  Eigen::Vector3d from, to;
  double diameterMeters = 0.0;
  // A patch of the crown's sheet: its outward direction (horizontal, unit); zero for a droplet.
  // A crown merged into one particle (narrower than a pixel) has crownMerged set instead.
  Eigen::Vector3d crownOutward = Eigen::Vector3d::Zero();
  bool crownMerged = false;
};

// How far the crown's sheet leans out from the vertical (crowns in Yarin's 2006 photographs
// open upwards at 20-40 degrees).
inline constexpr double kCrownLeanDeg = 30.0;

// What a patch of the crown's sheet facing `outward` (horizontal unit) mirrors towards the unit
// direction `towardsCamera`: the environment along mirrorDirection, with the reflectance of a thin
// film of water (both faces, incoherently: 2 R / (1 + R), R Fresnel's at that incidence). The face
// the camera sees is the outer one (its normal leans down) or the inner one (up).
struct SheetReflection {
  Eigen::Vector3d mirrorDirection = Eigen::Vector3d::UnitY();  // unit, world
  double reflectance = 0.0;
};
SheetReflection crownSheetReflection(const Eigen::Vector3d& outward,
                                     const Eigen::Vector3d& towardsCamera);

// The directions of the crown's kCrownPoints patches on the horizontal.
const std::array<Eigen::Vector3d, kCrownPoints>& crownDirections();
// The crown's and droplets' motion during [openSeconds, closeSeconds] (clipped to their lives);
// none when the splash is not alive then. A crown narrower than `pixelMeters` (a pixel's width
// at the impact's depth; 0: never) is one still particle at its centre with the area of its
// kCrownPoints patches: drawn under a pixel, it covers that pixel as much as they would together.
std::vector<SplashParticle> splashParticles(const Impact& impact, double openSeconds,
                                            double closeSeconds, double pixelMeters = 0.0);
// The same, appended to `out` (a frame's many impacts share one vector: no allocation each);
// without the droplets when `droplets` is false (the level of detail: dropletDiameterMeters).
void appendSplashParticles(const Impact& impact, double openSeconds, double closeSeconds,
                           double pixelMeters, std::vector<SplashParticle>& out,
                           bool droplets = true);

// A droplet's diameter, and the farthest it gets from the impact point (the steepest throw's
// range and height bound it): together they bound the largest a droplet can look.
double dropletDiameterMeters(const Impact& impact);
double dropletReachMeters(const Impact& impact);

}  // namespace pluvia::rain
