#pragma once
// Real spherical harmonics of any order, the environment's projection onto them, and the drop
// shading they give. Basis: Sloan, "Stupid SH Tricks", z as the pole, no Condon-Shortley
// phase, index l*l + l + m; for l <= 3 exactly the basis of shaders/common_sh.glsl.
#include <array>
#include <vector>

#include "image/equirect.h"

namespace pluvia::optics {

using ShCoefficients = std::vector<std::array<double, 3>>;  // (order+1)^2 RGB coefficients

// Y_lm(direction) for l = 0..order, written to basis ((order+1)^2 values). Unit direction.
void shBasis(int order, const std::array<double, 3>& direction, std::vector<double>& basis);

// Damping of band l against ringing (Gibbs) when the environment holds a very bright small
// source: negative lobes around a sun can make the SH radiance negative elsewhere.
enum class ShWindow { None, Hann, Lanczos };
double shWindowFactor(ShWindow window, int l, int order);

// L_lm = sum over texels of L * Y_lm(texel centre) * texel solid angle, then windowed.
ShCoefficients projectEnvironment(const EquirectMap& environment, int order,
                                  ShWindow window = ShWindow::None);

// sqrt(4 pi / (2l + 1)): turns the zonal coefficient d_l into band l of the transfer rotated to
// any view direction (rain::ShadingParams::transferZonal holds d_l times this).
double zonalRotationFactor(int l);

// The drop's radiance along `view` by the closed-form rotation of a zonal transfer
// (addition theorem): C = sum_l sqrt(4 pi / (2l + 1)) d_l sum_m Y_lm(view) L_lm, per channel with
// that channel's zonal coefficients d_l.
std::array<double, 3> shadeZonal(const ShCoefficients& environment,
                                 const std::array<std::vector<double>, 3>& zonal,
                                 const std::array<double, 3>& view);

// The rotated transfer vector sqrt(4 pi / (2l + 1)) d_l Y_lm(view) of one channel: what the
// paper precomputes per view direction.
std::vector<double> rotatedTransfer(const std::vector<double>& zonal,
                                    const std::array<double, 3>& view);

}  // namespace pluvia::optics
