#pragma once
// pluvia's default drop shading: the environment convolved once with the drop's transfer
// function, stored as an equirect map of drop radiance per view direction, and looked up per
// drop (bilinear, sampleEquirect). Like a prefiltered irradiance map, but with D(theta) as the
// kernel: E(v) = integral D(angle(v, w)) L(w) dw.
//
// Unlike low-order SH, nothing of D is cut off: the forward lobe (the refracted background),
// the reflection and the rainbow caustics all stay, so no c * B correction is needed. The
// error left is that of the grids: the environment is area-resampled to the input grid (the
// power of a sun is kept) and the result is interpolated between output texels.
#include <array>

#include "image/equirect.h"
#include "optics/drop_transfer.h"

namespace pluvia::optics {

struct RadianceMapSettings {
  // The map looked up per drop (outputWidth / 2 rows). 256 x 128 halves the worst error near a
  // sun against 128 x 64 for ~0.5 s more per environment (table in the optics report).
  int outputWidth = 256;
  int inputWidth = 512;      // the environment is resampled to this (a multiple of outputWidth)
  int bins = 2048;           // bins in cos(theta) of the transfer table
  int kernelSubsamples = 3;  // per input texel and axis: D averaged over the texel's footprint
};

// Per channel optics (dispersion: a different eta per channel).
EquirectMap buildDropRadianceMap(const EquirectMap& environment,
                                 const std::array<DropOptics, 3>& optics,
                                 const RadianceMapSettings& settings = {});

}  // namespace pluvia::optics
