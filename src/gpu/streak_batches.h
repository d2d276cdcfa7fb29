#pragma once
// The order in which the streaks of a frame are drawn, and the draws that carry them.
//
// On a software rasteriser (llvmpipe) the cost of a streak is the 4x4 pixel blocks it touches,
// and a thin slanted quad drawn as two triangles has nearly every block on their shared
// diagonal: each block is shaded twice. A wide GL line is rasterised as one parallelogram (4
// edge planes), so drawing a streak as a line halves the blocks shaded. The line width is draw
// state, not a vertex attribute, so the streaks are grouped into width classes (whole pixels,
// steps of at most 1.5x) and each class is one draw with the class's width; the fragment shader
// still decides coverage from the exact quad, so the wider parallelogram only costs discarded
// fragments.
//
// Drawing order: narrow classes first, instance order within a class. Wide streaks are the
// near ones, so this is roughly back to front, as "over" wants. Both renderers (GPU and
// renderRainCpu) composite in this order.
#include <cstddef>
#include <vector>

#include "rain/streak_types.h"

namespace pluvia::gpu {

// Streaks whose line would be wider than this are drawn as two triangles: a very wide
// parallelogram around a short streak would shade far more than its quad.
inline constexpr float kMaxStreakLineWidthPx = 64.0f;
// How far the rasterised primitive reaches past the exact quad on every side: vertices snap to
// the rasteriser's sub-pixel grid (1/256 px or finer), and the exact coverage test in the
// fragment shader must never find a pixel centre of the quad outside the primitive. Shared
// with shaders/rain_stroke.vert.
inline constexpr float kCoverageMarginPx = 1.0f / 16.0f;

// GL clips a wide line as its centre line, so a line whose centre leaves the viewport loses
// the pixels its width still covers inside the frame. The viewport therefore reaches this far
// past the frame on every side (half the widest line, and then some); the rasteriser still
// writes only the frame's pixels. Shared with shaders/rain_stroke.vert and frame_targets.cpp.
inline constexpr int kViewportGuardBandPx = 64;

struct StreakBatch {
  size_t first = 0;  // index into OrderedStreaks::streaks
  size_t count = 0;
  float lineWidthPx = 0.0f;  // the GL line width of the batch; 0: drawn as triangles
};

struct OrderedStreaks {
  std::vector<rain::StreakInstance> streaks;  // the visible streaks in drawing order
  std::vector<StreakBatch> batches;           // consecutive, covering `streaks`
};

// The line width that holds a streak's quad: widthPx across, divided by the cosine of the
// angle between the streak and the line's major axis (GL widens a line along its minor
// axis, x or y), plus the margin on both sides.
float lineWidthHolding(const rain::StreakInstance& streak);

// Drops the invisible streaks (zero width or alpha) and orders the rest for drawing.
OrderedStreaks orderForDrawing(const std::vector<rain::StreakInstance>& streaks);

}  // namespace pluvia::gpu
