#pragma once
// Level of detail for far rain (rain.lod_px): the drops whose projected diameter is under a few
// pixels are faint (a streak's alpha falls as 1 / depth) and many (drops in a depth slab grow
// as depth^2), so they hold most of a frame's streak pixels and little of its picture. They are
// not drawn as quads but as a statistically equivalent veil:
//   - each far streak's coverage mass, m = alpha * meanMatte(stroke) * width * (length + width)
//     (px^2: the matte integrated over its quad), is split over points along its axis at most
//     one cell apart, and each point in front of the scene there is splatted bilinearly into a
//     grid of kCellPx cells with the streak's radiance C (plus the local lights' term at its
//     mean bead factor) and depth;
//   - a cell holding mass M over its area a gets coverage A = 1 - exp(-M / a), the mean of
//     1 - prod(1 - alpha_i) over many faint streaks at random places, and the mass-weighted
//     mean radiance, premultiplied by A;
//   - a pixel takes the bilinear blend of its four nearest cell centres (the splat's adjoint,
//     so mass is kept), each only where the cell's mass-weighted depth is in front of the scene.
// The near streaks are composited over the veil ("over": L = L_near + (1 - A_near) L_veil);
// far drops are the narrowest streaks, which the renderers draw first anyway
// (streak_batches.h). What it keeps: the layer's coverage and radiance averaged over a few
// cells; what it loses: each far streak's own line, at most its alpha * C at one pixel.
#include <vector>

#include "rain/streak_types.h"

namespace pluvia::gpu {

class FarDropLayer {
 public:
  // Edge of a veil cell in pixels: the points along a streak are at most this far apart.
  static constexpr int kCellPx = 8;

  // The mean of each stroke's matte over its rectangle (rain::StrokeAtlas::rects order).
  void setStrokeMeans(const rain::StrokeAtlas& atlas);

  // The veil of `streaks` (inputs already checked, rain_inputs.h) for a width x height frame.
  // sceneDepth: the frame's "depth" plane (any value; non-finite is far) or null (all far).
  void build(int width, int height, const std::vector<rain::StreakInstance>& streaks,
             const rain::ShadingParams& shading, const float* sceneDepth);
  // True when no far streak reached the frame: the veil is transparent black everywhere.
  bool empty() const { return empty_; }

  // The veil's premultiplied layer (alpha * C, alpha) at pixels [x0, x1] of row y, written to
  // r[0 .. x1 - x0] and so on. depthRow: row y of the scene depth (raw), or null.
  void row(int y, int x0, int x1, const float* depthRow, float* r, float* g, float* b,
           float* a) const;

  // Composites an interleaved premultiplied RGBA layer (the EGL path's read-back) over the veil.
  void underlay(const float* sceneDepth, std::vector<float>& rgba) const;

 private:
  int width_ = 0, height_ = 0, cellsX_ = 0, cellsY_ = 0;
  bool empty_ = true;
  std::vector<float> strokeMeans_;
  // Per cell, interleaved: premultiplied r, g, b, a and the mass-weighted depth (metres).
  std::vector<float> cells_;
  std::vector<double> sums_;  // scratch: mass, mass * C (3), mass * depth per cell
};

}  // namespace pluvia::gpu
