#pragma once
// The paper's way of rotating the drop's transfer vector: precomputed for 98,304 view
// directions (a cube map of 6 x 128 x 128 texels), looked up at the nearest texel. Kept to
// compare its memory, speed and error with the closed-form rotation (sh.h, rotatedTransfer),
// which needs only the order + 1 zonal coefficients.
#include <array>
#include <vector>

#include "optics/sh.h"

namespace pluvia::optics {

class PaperTransferTable {
 public:
  // zonal: d_l per channel, all of the same order.
  explicit PaperTransferTable(const std::array<std::vector<double>, 3>& zonal, int faceSize = 128);

  // C = transfer(nearest texel to view) . environment SH, per channel.
  std::array<double, 3> shade(const ShCoefficients& environment,
                              const std::array<double, 3>& view) const;

  int directions() const { return 6 * faceSize_ * faceSize_; }
  size_t bytes() const { return transfers_.size() * sizeof(float); }

 private:
  size_t texelIndex(const std::array<double, 3>& view) const;

  int faceSize_;
  int coefficients_;
  std::vector<float> transfers_;  // per texel, per channel, (order+1)^2 floats
};

}  // namespace pluvia::optics
