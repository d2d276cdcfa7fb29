#include "optics/skylight_scattering.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "optics/drop_radiance_map.h"
#include "optics/drop_transfer.h"

namespace pluvia::optics {
namespace {

constexpr int kReferenceBins = 8192;

std::array<double, 3> meanRadiance(const EquirectMap& map) {
  std::array<double, 3> sum{0, 0, 0};
  for (int y = 0; y < map.height; ++y) {
    const double omega = equirectTexelSolidAngle(map.width, map.height, y);
    for (int x = 0; x < map.width; ++x) {
      for (int c = 0; c < 3; ++c) sum[size_t(c)] += omega * map.texel(x, y)[c];
    }
  }
  for (double& s : sum) s /= 4.0 * M_PI;
  return sum;
}

}  // namespace

SkylightTable buildSkylightTable(const EquirectMap& environment, int tableWidth, int inputWidth) {
  RadianceMapSettings settings;
  settings.outputWidth = tableWidth;
  // A multiple of the table's width, as the radiance map needs.
  settings.inputWidth = std::max(1, (inputWidth + tableWidth - 1) / tableWidth) * tableWidth;
  const DropOptics water;  // eta 1.333, 9 terms; no dispersion: the fog is white
  SkylightTable table;
  table.dropRadiance = buildDropRadianceMap(environment, {water, water, water}, settings);
  const std::array<double, 3> mean = meanRadiance(environment);
  for (int c = 0; c < 3; ++c) table.meanRadiance[size_t(c)] = float(mean[size_t(c)]);
  return table;
}

std::array<float, 3> skylightInscatter(const SkylightTable& table, const SkylightMedium& medium,
                                       const std::array<double, 3>& view) {
  const double sigma = medium.extinctionPerMeter();
  if (!(sigma > 0.0)) return {0, 0, 0};
  const float rainWeight = float(medium.rainScatteringPerMeter() / sigma);
  const std::array<float, 3> drop =
      sampleEquirect(table.dropRadiance, float(view[0]), float(view[1]), float(view[2]));
  std::array<float, 3> out{};
  for (int c = 0; c < 3; ++c) {
    out[size_t(c)] =
        rainWeight * drop[size_t(c)] + (1.0f - rainWeight) * table.meanRadiance[size_t(c)];
  }
  return out;
}

std::array<double, 3> skylightReference(const EquirectMap& environment,
                                        const SkylightMedium& medium,
                                        const std::array<double, 3>& view, double pathMeters,
                                        int steps) {
  if (environment.empty()) throw std::invalid_argument("skylight reference: empty environment");
  if (steps < 2 || steps % 2 != 0) throw std::invalid_argument("skylight reference: odd steps");
  static const TransferTable d = binTransfer(DropOptics{}, kReferenceBins);
  // E_D(v): every texel of the environment, D at the angle to its centre.
  std::array<double, 3> drop{0, 0, 0};
  for (int y = 0; y < environment.height; ++y) {
    const double omega = equirectTexelSolidAngle(environment.width, environment.height, y);
    for (int x = 0; x < environment.width; ++x) {
      const std::array<double, 3> w =
          equirectTexelDirection(environment.width, environment.height, x, y);
      const double weight = omega * d.at(view[0] * w[0] + view[1] * w[1] + view[2] * w[2]);
      const float* l = environment.texel(x, y);
      for (int c = 0; c < 3; ++c) drop[size_t(c)] += weight * l[c];
    }
  }
  const std::array<double, 3> mean = meanRadiance(environment);
  const double sigma = medium.extinctionPerMeter();
  std::array<double, 3> out{0, 0, 0};
  if (!(sigma > 0.0) || !(pathMeters > 0.0)) return out;
  // Huang's Eq. 4 for one segment: integral_0^d L_in(x) sum_i p_i D_i exp(-sigma x) dx, the
  // per-point source sigma_r E_D + sigma_f Lbar constant along a homogeneous ray.
  std::array<double, 3> source{};
  for (int c = 0; c < 3; ++c) {
    source[size_t(c)] =
        medium.rainScatteringPerMeter() * drop[size_t(c)] + medium.fogPerMeter * mean[size_t(c)];
  }
  const double h = pathMeters / steps;
  double integral = 0.0;
  for (int k = 0; k <= steps; ++k) {
    const double weight = (k == 0 || k == steps) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0);
    integral += weight * std::exp(-sigma * k * h);
  }
  integral *= h / 3.0;
  for (int c = 0; c < 3; ++c) out[size_t(c)] = source[size_t(c)] * integral;
  return out;
}

EquirectMap cieOvercastSky(int width, const std::array<float, 3>& zenithRgb, double groundAlbedo) {
  const int height = width / 2;
  EquirectMap map(width, height);
  for (int y = 0; y < height; ++y) {
    const double cosTheta = equirectTexelDirection(width, height, 0, y)[1];
    const double scale = cosTheta > 0.0 ? (1.0 + 2.0 * cosTheta) / 3.0 : groundAlbedo * 7.0 / 9.0;
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < 3; ++c) map.texel(x, y)[c] = float(zenithRgb[size_t(c)] * scale);
    }
  }
  return map;
}

}  // namespace pluvia::optics
