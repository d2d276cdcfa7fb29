#pragma once
// Level of detail for far rain (rain.lod_px): the drops whose projected diameter is under a few
// pixels are faint (a streak's alpha falls as 1 / depth) and many (drops in a depth slab grow
// as depth^2), so they hold most of a frame's streaks and little of its picture. They are not
// drawn as textured quads but as single-pixel lines carrying the same coverage:
//   - the line runs along the quad's axis over its whole length, length + width (head - axis *
//     width / 2 to tail + axis * width / 2), sampled once per pixel row it crosses (per column
//     for a streak nearer horizontal than vertical), each sample split between the two pixels
//     nearest to it (Wu's antialiased line);
//   - the samples share the streak's coverage mass m = alpha * meanMatte(stroke) * width *
//     (length + width) (px^2: its matte integrated over its quad), so a pixel takes alpha =
//     min(1, share of m), and blends alpha * C "over" the layer, C the streak's radiance (plus
//     the local lights' term at its mean bead factor over the streak), where the streak is in front
//     of the scene.
// What it keeps: each far streak's place, direction, length, depth test, radiance and coverage;
// what it loses: its matte's texture and its width (one to two pixels instead of widthPx).
// Far drops are the narrowest streaks, which the renderers draw first anyway (streak_batches.h),
// so the near streaks are composited over the lines.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rain/streak_types.h"

namespace pluvia::gpu {

// A premultiplied layer, one plane per channel, and the scene depth (null: all far).
struct LinePlanes {
  float* r;
  float* g;
  float* b;
  float* a;
  const float* depth;
  int width, height;
};

class FarDropLines {
 public:
  // The mean of each stroke's matte over its rectangle (rain::StrokeAtlas::rects order).
  void setStrokeMeans(const rain::StrokeAtlas& atlas);
  // Blends the lines of `streaks` (inputs already checked, rain_inputs.h) over the layer, in
  // order. Rows are drawn in parallel bands: each pixel is blended by one thread, in order.
  void draw(const std::vector<rain::StreakInstance>& streaks, const rain::ShadingParams& shading,
            const LinePlanes& target);

 private:
  // One streak's line: from (x0, y0) to (x1, y1) along its major axis (y when steep: the
  // coordinates are swapped for a flat one), the rows (columns) whose centres it crosses and
  // the alpha each of their samples carries.
  struct Line {
    float minor0, major0, slope;  // minor coordinate = minor0 + slope * (major - major0)
    int first, last;              // major pixel range (inclusive); first > last: nothing
    bool steep;                   // major axis y
    float alphaPerSample;         // the streak's mass over its samples
    float depthMeters;
    std::array<float, 3> color;  // C
  };
  std::vector<float> strokeMeans_;
  // Scratch kept between frames: the lines, and their indices binned to bands of rows.
  std::vector<Line> lines_;
  std::vector<uint32_t> binned_;
  std::vector<size_t> bandStart_, bandNext_;
};

}  // namespace pluvia::gpu
