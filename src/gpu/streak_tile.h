#pragma once
// Drawing the streaks of one tile of the frame, for StreakRasterCpu (streak_raster_cpu.h): the
// per-pixel work of the CPU backend, with an AVX2 + FMA path chosen at run time where the CPU
// has it and a portable one elsewhere.
#include <array>
#include <cstddef>

namespace pluvia::gpu {

// What one streak needs to be drawn, computed once per frame (streak_raster_cpu.cpp).
struct StreakSetup {
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
  float rectX0, rectY0, rectWidth, rectHeight;  // texel coordinates in the padded atlas
  std::array<float, 3> radiance;                // C
  // The local lights' radiance, beaded along v (rain::localLightBead); hasLocal: any is > 0.
  std::array<float, 3> local;
  float beadCycles, beadPhase, glintMode20, glintMode31;
  bool hasLocal;
  int x0, y0, x1, y1;  // pixels that may hold centres (inclusive)
};

// The frame's rain layer (premultiplied alpha * C, one plane per channel) and scene depth.
struct TileTarget {
  float* r;
  float* g;
  float* b;
  float* a;
  const float* depth;  // metres; null: no depth plane (everything far)
  int width;           // of the frame, the planes' row stride
  bool cleared;        // the planes hold zeros already (just made): no need to clear a tile
};

// The stroke atlas with one texel of clamp-to-edge border on every side, stored as the 2 x 2
// neighbourhoods a bilinear sample reads: texel (x, y) holds 4 floats, the texels (x, y),
// (x + 1, y), (x, y + 1) and (x + 1, y + 1) (clamped at the last row and column), so a sample
// is one 16-byte load.
struct PaddedAtlas {
  const float* quads;  // stride * rows * 4 floats
  int stride;          // texels per row
};

// Clears the tile [x0, x1] x [y0, y1] (inclusive) of the layer (unless target.cleared) and draws
// `count` streaks into it in order: the pixels whose centres have u, v in [0, 1] and lie in front
// of the scene blend alpha * (C + bead(v) * local) over the layer, alpha = clamp(matte(u, v) *
// streak alpha, 0, 1), matte the bilinear atlas sample. Touches no pixel outside the tile.
// portableOnly: never the AVX2 path.
void drawTile(const StreakSetup* streaks, size_t count, const PaddedAtlas& atlas,
              const TileTarget& target, int x0, int y0, int x1, int y1, bool portableOnly = false);

namespace detail {
// The two paths, for the test that compares them; drawTile picks one.
void drawTilePortable(const StreakSetup* streaks, size_t count, const PaddedAtlas& atlas,
                      const TileTarget& target, int x0, int y0, int x1, int y1);
// Needs AVX2 and FMA, and a tile at least 4 pixels wide.
void drawTileAvx2(const StreakSetup* streaks, size_t count, const PaddedAtlas& atlas,
                  const TileTarget& target, int x0, int y0, int x1, int y1);
bool cpuHasAvx2();
}  // namespace detail

}  // namespace pluvia::gpu
