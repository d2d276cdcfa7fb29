#pragma once
// The drop-shading methods pluvia offers, behind one small interface, for the renderer, the
// shade-drop command and the optics report:
//   default: the environment convolved with D (drop_radiance_map.h), looked up per drop;
//   paper:   Wang et al.: 16 SH coefficients (order 3), 9 terms of D, C' = C + 0.7 B, with B the
//            environment straight behind the drop;
//   trace:   the Monte-Carlo reference (drop_trace.h).
#include <array>
#include <string>

#include "image/equirect.h"
#include "optics/drop_radiance_map.h"
#include "optics/sh.h"

namespace pluvia::optics {

enum class DropMethod { Default, Paper, Trace };
// "default", "paper", "trace"; throws std::invalid_argument naming the word otherwise.
DropMethod parseDropMethod(const std::string& word);

inline constexpr int kPaperShOrder = 3;
inline constexpr int kPaperTerms = 9;
inline constexpr double kPaperBackgroundWeight = 0.7;
// Terms of D the default method keeps: the power left out beyond it is below 1e-3 for
// eta = 1.333 (see the optics report and tests/optics/test_drop_transfer.cpp).
inline constexpr int kDefaultTerms = 20;
inline constexpr double kWaterEta = 1.333;
// Dispersion of water, R / G / B (the refractive index of water at about 650 / 550 / 450 nm).
inline constexpr std::array<double, 3> kWaterEtaDispersion = {1.331, 1.333, 1.338};

// Per channel optics with the same number of terms.
std::array<DropOptics, 3> channelOptics(const std::array<double, 3>& eta, int terms);

// What the paper's method needs per environment.
struct PaperShading {
  ShCoefficients environmentSh;
  std::array<std::vector<double>, 3> zonal;  // d_l per channel
  double backgroundWeight = kPaperBackgroundWeight;
};
PaperShading preparePaperShading(const EquirectMap& environment, const std::array<double, 3>& eta,
                                 int order = kPaperShOrder, int terms = kPaperTerms,
                                 ShWindow window = ShWindow::None);
// C' = max(C, 0) + c * B, B = sampleEquirect(environment, view).
std::array<double, 3> shadePaper(const PaperShading& paper, const EquirectMap& environment,
                                 const std::array<double, 3>& view);

}  // namespace pluvia::optics
