#pragma once
// A stroke matte's own size, measured the same way wherever a matte is measured: when
// `pluvia strokes` cuts it from footage (derain/stroke_extraction.cpp) and when the renderer
// fits it to a drop's streak (rain/stroke_library.h, strokeQuadScales()).
#include <cstddef>
#include <vector>

namespace pluvia::rain {

// The matte of a vertical stroke, `rows` x `cols` floats with `strideFloats` between rows.
struct StrokeProfile {
  std::vector<double> rowPeak, rowSum;  // per row: the largest value, and the sum across
  double along = 0.0;                   // the largest row sum: the profile along's maximum
  int first = -1, last = -1;            // first and last rows at or above half of `along`
  // The full length at half maximum of the profile along (row sums, which unlike row peaks do
  // not change with where a thin stroke falls between pixels), crossings interpolated.
  double lengthPx = 0.0;
  // The mean equivalent width across (row sum over row peak) over the rows above half maximum.
  double widthPx = 0.0;
  double contrast = 0.0;  // the largest value
};

StrokeProfile strokeProfile(const float* alpha, size_t strideFloats, int cols, int rows);

}  // namespace pluvia::rain
