#pragma once
// The CPU backend of RainRenderer: a rasteriser made for streaks, for machines whose EGL device
// is a software one (llvmpipe), where a general-purpose GL rasteriser spends most of its time
// on what a streak does not need (triangle setup, 4x4 blocks half outside a 2 px wide quad,
// a JIT'd fragment pipeline per block).
//
// Same maths as the EGL path and as renderRainCpu (rain_renderer.h, rain_cpu.cpp): each
// streak's quad (streak_quad.h) covers the pixels whose centres have matte coordinates u, v in
// [0, 1]; the matte is the atlas sampled bilinearly with clamp-to-edge at (u, v) of the
// stroke's rectangle; the fragment is dropped behind the scene's depth; the premultiplied layer
// of alpha * C is blended in drawing order (streak_batches.h); c * B enters afterwards, as
// compositeRainPlanes() does for both. What differs is the evaluation:
//   - the frame is cut into tiles; each streak is binned (in drawing order) to the tiles its
//     bounding box touches, and tiles are drawn in parallel (TBB), so every pixel is blended by
//     one thread in drawing order and the picture does not depend on the thread count;
//   - in each tile a streak is walked row by row over the span of x where its quad can hold
//     pixel centres (both ends linear in the row), the u, v test deciding each pixel, with u
//     and v stepped from the row's start (a multiply by 1 / width instead of a divide): the
//     same coverage as the other renderers except within about 1e-5 px of an edge;
//   - the atlas is copied with a one-texel border of repeated edge texels, which is exactly
//     clamp-to-edge and needs no clamping per sample.
#include <array>
#include <cstdint>
#include <vector>

#include "image/image.h"
#include "rain/streak_types.h"

namespace pluvia::gpu {

class StreakRasterCpu {
 public:
  void setStrokeAtlas(const rain::StrokeAtlas& atlas);
  int strokeCount() const { return static_cast<int>(rects_.size()); }

  // `streaks` are the visible ones in drawing order (orderForDrawing), inputs already checked
  // (rain_inputs.h). Sets frame.rgba's RGB and the rain planes as RainRenderer::render does.
  void render(Image& frame, const std::vector<rain::StreakInstance>& streaks,
              const rain::ShadingParams& shading);

  // Tile edge in pixels: small enough to give both cores many tiles on a 720x480 frame, large
  // enough that most streaks fall in one or two tiles.
  static constexpr int kTilePx = 32;

  // What one streak needs, computed once per frame.
  struct Setup {
    // The centres cx of row y (centre cy = y + 0.5) that may lie on the quad: from
    // max(lo[0] + loSlope[0] * cy, lo[1] + ...) to min(hi[0] + hiSlope[0] * cy, hi[1] + ...),
    // one pair of bounds per matte coordinate (u across, v along); a coordinate that does not
    // change along a row bounds nothing (-inf, +inf).
    std::array<float, 2> lo, loSlope, hi, hiSlope;
    // Matte coordinates at the centre of pixel (x, y), with rx = (x - headPixelX) + headOffsetX
    // and ry = y + 0.5 - headY: u = 0.5 + (rx * -axisY + ry * axisX) / width, v = (rx * axisX +
    // ry * axisY + width / 2) / (length + width), as StreakQuad::matteCoordinates.
    int headPixelX;
    float headOffsetX, headY, axisX, axisY;
    float halfWidth, inverseWidth, inverseLengthPlusWidth;
    float alpha, depthMeters;
    float rectX0, rectY0, rectWidth, rectHeight;  // in the padded atlas's texels
    std::array<float, 3> radiance;                // C
    int x0, y0, x1, y1;                           // pixels that may hold centres (inclusive)
  };

 private:
  // The atlas with one texel of clamp-to-edge border on every side.
  int paddedWidth_ = 0, paddedHeight_ = 0;
  std::vector<float> padded_;
  std::vector<std::array<float, 4>> rects_;

  // Scratch kept between frames: a long clip allocates once.
  std::vector<Setup> setups_, binned_;
  std::vector<size_t> tileStart_, next_;
};

}  // namespace pluvia::gpu
