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
// compositeRainLayer() does for the EGL path (here tile by tile, compositeRainPixels()). What
// differs is the evaluation:
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

#include "gpu/far_drop_lines.h"
#include "gpu/streak_tile.h"
#include "image/image.h"
#include "rain/streak_types.h"

namespace pluvia::gpu {

class StreakRasterCpu {
 public:
  // portableOnly: never the AVX2 path (for the test that compares the two).
  explicit StreakRasterCpu(bool portableOnly = false) : portableOnly_(portableOnly) {}

  void setStrokeAtlas(const rain::StrokeAtlas& atlas);
  int strokeCount() const { return static_cast<int>(rects_.size()); }

  // `streaks` are the visible ones in drawing order (orderForDrawing), inputs already checked
  // (rain_inputs.h). Sets frame.rgba's RGB and the rain planes as RainRenderer::render does.
  // farStreaks: drawn first as lines by farLines (far_drop_lines.h), the streaks over them.
  void render(Image& frame, const std::vector<rain::StreakInstance>& streaks,
              const rain::ShadingParams& shading, FarDropLines* farLines = nullptr,
              const std::vector<rain::StreakInstance>* farStreaks = nullptr);

  // Tile edge in pixels: small enough to give both cores many tiles on a 720x480 frame, large
  // enough that most streaks fall in one or two tiles.
  static constexpr int kTilePx = 64;
  // Streaks are set up and binned in parallel chunks of about this many (at most kMaxChunks).
  static constexpr size_t kStreaksPerChunk = 4096;
  static constexpr size_t kMaxChunks = 64;

 private:
  bool portableOnly_;
  // The atlas with one texel of clamp-to-edge border on every side, as PaddedAtlas's quads.
  int paddedWidth_ = 0, paddedHeight_ = 0;
  std::vector<float> quads_;
  std::vector<std::array<float, 4>> rects_;

  // Scratch kept between frames: a long clip allocates once.
  std::vector<StreakSetup> setups_, binned_;
  std::vector<size_t> tileStart_, chunkCounts_;
};

}  // namespace pluvia::gpu
