#pragma once
// `pluvia report fog`: the skylight fog model (optics/skylight_scattering.h) per table size
// against its reference (the environment summed texel by texel with D(theta), the in-scattering
// marched along the ray), with the time to build the table and to evaluate a pixel; and the
// exponential model (one airlight, the environment's horizon) against the same reference.
// Relative error of one sample: the worst channel of |model - reference| / reference for a black
// surface at a path length of 5 m, 300 m and 5 km, over random view directions (fixed seed).
#include <array>
#include <string>
#include <vector>

#include "image/equirect.h"

namespace pluvia::lab {

struct FogReportSettings {
  int directions = 48;
  double rainExtinctionPerMeter = 6e-3;  // about 100 mm/h
  double fogPerMeter = 1e-3;
};

struct FogReportRow {
  std::string environment;  // "CIE overcast", a file name
  std::string model;        // "skylight 64x32", "exponential (horizon)"
  double meanRelativeError = 0.0;
  double maxRelativeError = 0.0;
  double buildMilliseconds = 0.0;
  double nanosecondsPerPixel = 0.0;
};

// One block of rows per environment (name, map).
std::vector<FogReportRow> runFogReport(
    const std::vector<std::pair<std::string, EquirectMap>>& environments,
    const FogReportSettings& settings);
std::string formatFogReport(const std::vector<FogReportRow>& rows);

// `count` unit directions uniform over the sphere (normalised Gaussians, fixed seed).
std::vector<std::array<double, 3>> randomViewDirections(int count, unsigned seed);

}  // namespace pluvia::lab
