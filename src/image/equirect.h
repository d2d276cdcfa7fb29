#pragma once
// Equirectangular (latitude-longitude) RGB maps: environments and the per-direction drop
// radiance that the rain shader looks up. The convention is exact, because checks outside this
// repository use it:
//   world +Y is up; a unit direction d = (x, y, z) maps to
//     u = 0.5 + atan2(x, -z) / (2 pi),   v = acos(y) / pi,
//   with (u, v) = (0, 0) at the top-left corner of the image, so the image centre looks along
//   -Z. Texel (i, j) covers u in [i, i+1] / width and v in [j, j+1] / height; its centre is at
//   ((i + 0.5) / width, (j + 0.5) / height).
#include <array>
#include <cstddef>
#include <vector>

namespace pluvia {

struct EquirectMap {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;  // width * height * 3, row 0 at the top (+Y)

  EquirectMap() = default;
  EquirectMap(int w, int h);  // zeros
  bool empty() const { return width <= 0 || height <= 0; }
  float* texel(int x, int y) {
    return rgb.data() + (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3;
  }
  const float* texel(int x, int y) const {
    return rgb.data() + (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3;
  }
};

// (u, v) of a unit direction, as above; u in [0, 1), v in [0, 1].
std::array<double, 2> equirectUv(const std::array<double, 3>& direction);
// The unit direction at (u, v).
std::array<double, 3> equirectDirection(double u, double v);
// The unit direction through the centre of texel (x, y) of a width x height map.
std::array<double, 3> equirectTexelDirection(int width, int height, int x, int y);
// Solid angle of one texel in row y, in steradians: (2 pi / width) (cos theta0 - cos theta1).
double equirectTexelSolidAngle(int width, int height, int y);

// Bilinear lookup between texel centres: wraps around in u, clamps to the first and last rows
// in v. All arithmetic in float, step for step as sampleRadianceMap() in
// shaders/rain_stroke.vert, whose CPU twin this is.
std::array<float, 3> sampleEquirect(const EquirectMap& map, float x, float y, float z);

// Solid-angle mean radiance over the band of elevations [minElevationDeg, maxElevationDeg]
// (0 the horizon, 90 the zenith), each row weighted by the part of it inside the band.
std::array<float, 3> equirectBandMean(const EquirectMap& map, double minElevationDeg,
                                      double maxElevationDeg);

// A map of constant radiance.
EquirectMap uniformEquirect(int width, int height, const std::array<float, 3>& radiance);

// Area resampling to width x height (up or down, any ratio): every output texel is the
// solid-angle-weighted mean of the input over its footprint, so the power (radiance times solid
// angle) of the map is kept and a sun smaller than an output texel keeps its energy.
EquirectMap resampleEquirect(const EquirectMap& map, int width, int height);

}  // namespace pluvia
