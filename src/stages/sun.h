#pragma once
// The sun: its direction and irradiance, from a given elevation and azimuth or found in an
// environment map as its brightest spot.
#include <array>
#include <optional>

#include <Eigen/Core>

#include "image/equirect.h"

namespace pluvia {

struct Sun {
  Eigen::Vector3d direction{0, 1, 0};            // unit, world, toward the sun
  std::array<double, 3> irradianceRgb{0, 0, 0};  // on a surface facing it
};

// Elevation above the horizon, azimuth from world -Z toward +X (degrees).
Eigen::Vector3d sunDirection(double elevationDeg, double azimuthDeg);

// The brightest spot of `environment`, when it stands out (peak luminance at least
// kSunContrast times the map's mean): direction of the peak texel of a 256 x 128 resampling
// (power kept) and the irradiance of the texels within kSunRadiusDeg of it, less the mean sky
// around. Empty when nothing stands out (overcast).
inline constexpr double kSunContrast = 20.0;
inline constexpr double kSunRadiusDeg = 3.0;
std::optional<Sun> findSun(const EquirectMap& environment);

}  // namespace pluvia
