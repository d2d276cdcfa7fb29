#pragma once
// Skylight scattered by rain and fog into a view ray (Huang et al. 2006 section 1.1, Eq. 4-6):
// the environment lights every particle along the ray; each scatters part of it toward the
// camera, and what it sends is attenuated on its way back.
//
// The medium is homogeneous (one segment of Huang's Eq. 5-6: with constant particle densities
// the segments' sums collapse to a single one, as the paper notes under Eq. 6) and of two kinds:
//  - rain: Marshall-Palmer drops. Their extinction (rain/drop_physics.h) counts twice the
//    geometric cross-section; the half that is diffraction stays within a degree of the ray and
//    is treated as not scattered, so rain scatters sigma_r = rainExtinction / 2 with the drop's
//    transfer function D(theta) (optics/drop_transfer.h, geometric optics) as its phase function;
//  - fog: small droplets scattering isotropically (Huang's k = 1 / (4 pi)), sigma_f = density.
// Water absorbs little: all extinction is scattering (albedo 1), single scattering, and the
// environment (measured at the camera, inside the rain) lights every point of the ray alike.
// With sigma = sigma_r + sigma_f the radiance a camera sees along unit view v to a surface of
// radiance L_s at distance d is then
//   L = L_in(v) (1 - exp(-sigma d)) + L_s exp(-sigma d),
//   L_in(v) = (sigma_r E_D(v) + sigma_f Lbar) / sigma,
//   E_D(v) = integral D(angle(v, w)) L(w) dw,   Lbar = (1 / 4 pi) integral L(w) dw,
// E_D being the drop radiance map (optics/drop_radiance_map.h) at a small table size. The sky
// (d infinite) is left as it is: it is already the light that came through the whole rain.
#include <array>

#include "image/equirect.h"

namespace pluvia::optics {

struct SkylightMedium {
  double rainExtinctionPerMeter = 0.0;  // rain/drop_physics.h, diffraction included
  double fogPerMeter = 0.0;             // fog.density
  double rainScatteringPerMeter() const { return 0.5 * rainExtinctionPerMeter; }
  double extinctionPerMeter() const { return rainScatteringPerMeter() + fogPerMeter; }
};

// E_D(v) as a tableWidth (even) x tableWidth / 2 equirect map (the environment resampled to
// inputWidth, rounded up to a multiple of tableWidth, first), and Lbar: what a medium of any
// rain-to-fog mix needs.
struct SkylightTable {
  EquirectMap dropRadiance;             // E_D per view direction
  std::array<float, 3> meanRadiance{};  // Lbar
};
SkylightTable buildSkylightTable(const EquirectMap& environment, int tableWidth = 64,
                                 int inputWidth = 256);

// L_in(v) from the table (bilinear in the map), per channel.
std::array<float, 3> skylightInscatter(const SkylightTable& table, const SkylightMedium& medium,
                                       const std::array<double, 3>& view);

// The reference: L for a black surface (L_s = 0) at `pathMeters` (finite), with E_D summed over
// every texel of the environment at its own resolution (D from a 8192-bin table) and the
// in-scattering integral_0^d sigma exp(-sigma x) L_in dx marched by composite Simpson's rule in
// `steps` steps (even).
std::array<double, 3> skylightReference(const EquirectMap& environment,
                                        const SkylightMedium& medium,
                                        const std::array<double, 3>& view, double pathMeters,
                                        int steps = 64);

// The CIE standard overcast sky, L(theta) = Lz (1 + 2 cos theta) / 3 over the upper hemisphere
// (theta from the zenith), above a grey ground of the given albedo lit by it: the ground's
// radiance is albedo * E / pi with the sky's horizontal irradiance E = 7 pi Lz / 9.
EquirectMap cieOvercastSky(int width, const std::array<float, 3>& zenithRgb,
                           double groundAlbedo = 0.2);

}  // namespace pluvia::optics
