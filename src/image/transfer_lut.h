#pragma once
// A colour conversion without channel crosstalk (each output channel a function of the same
// input channel: transfer curves, exponents, per-channel scales) as one lookup table per
// channel, linearly interpolated, in place of evaluating the curve per value. OpenColorIO's
// own processor evaluates pow() per value (the default optimisation's fast pow measured no
// faster here, see color.cpp); the table is several times faster and stays within 1e-6 of it
// (tests/image/test_transfer_lut.cpp).
//
// The nodes are spaced by the float format itself: 1024 per octave from 2^-16 to 2^8, so the
// spacing is 1/1024 of the value everywhere and a smooth curve's interpolation error is
// relative (at most p (p - 1) / 8 / 1024^2 for a power p: 4e-7 for the sRGB decode's 2.4).
// Exactly 0 is a node of its own. Any other value (negative, below 2^-16, 256 or above, NaN,
// infinite) is outside the table: its pixel goes through the exact function instead. Where the
// CPU has AVX2 the lookups run two pixels at a time (gathers), with the same result bit for bit.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace pluvia {

class TransferLut {
 public:
  // Converts `count` RGB triples (stride 3 floats) in place, exactly.
  using ExactRgb = std::function<void(float* rgb, size_t count)>;

  // Samples `exact` at every node.
  explicit TransferLut(const ExactRgb& exact);

  // Converts the RGB of `count` RGBA pixels in place (alpha untouched). Pixels with a value
  // outside the table are converted by `exact`; returns how many.
  size_t apply(float* rgba, size_t count) const;

  static constexpr int kNodesPerOctave = 1024;
  static constexpr int kLowestExponent = -16;  // the table covers [2^-16, 2^8)
  static constexpr int kOctaves = 24;

 private:
  ExactRgb exact_;
  // R's table, then G's, then B's; per node the value and the step to the next node.
  std::vector<float> tables_;
  float atZero_[3] = {0, 0, 0};
};

}  // namespace pluvia
