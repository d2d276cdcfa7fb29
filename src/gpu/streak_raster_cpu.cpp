#include "gpu/streak_raster_cpu.h"

#include <algorithm>
#include <cmath>

#include "gpu/rain_inputs.h"
#include "gpu/streak_quad.h"
#include "gpu/streak_radiance.h"
#include "gpu/streak_tile.h"
#include "util/parallel.h"

namespace pluvia::gpu {
namespace {

using Setup = StreakSetup;

constexpr std::array<const char*, 4> kRainPlaneNames = {"rain.R", "rain.G", "rain.B", "rain.A"};

// The pixels whose centres may lie on the quad, as in renderRainCpu's candidatePixels(); an
// empty range (x0 > x1) when the quad misses the frame.
void boundingPixels(const StreakQuad& quad, int width, int height, Setup& setup) {
  float minX, minY, maxX, maxY;
  quad.bounds(minX, minY, maxX, maxY);
  // Pixel x has its centre at x + 0.5: the centres inside [min, max] are ceil(min - 0.5) ..
  // floor(max - 0.5); one more on each side for rounding.
  auto first = [](float v, int size) {
    return static_cast<int>(std::clamp(std::ceil(v - 0.5f) - 1.0f, 0.0f, static_cast<float>(size)));
  };
  auto last = [](float v, int size) {
    return static_cast<int>(
        std::clamp(std::floor(v - 0.5f) + 1.0f, -1.0f, static_cast<float>(size - 1)));
  };
  setup.x0 = first(minX, width), setup.x1 = last(maxX, width);
  setup.y0 = first(minY, height), setup.y1 = last(maxY, height);
}

// Bounds on the centres cx of a row from lo <= offset + slope * cx + rowSlope * cy <= hi, as
// cx >= lo' + loSlope * cy and cx <= hi' + hiSlope * cy. A slope too small to divide by leaves
// x unbounded: the per-pixel test (and the bounding box) still decide.
void boundCentres(float offset, float slope, float rowSlope, float lo, float hi, Setup& setup,
                  int which) {
  constexpr float kMinSlope = 1e-6f;
  if (std::abs(slope) < kMinSlope) {
    setup.lo[which] = -INFINITY, setup.hi[which] = INFINITY;
    setup.loSlope[which] = setup.hiSlope[which] = 0.0f;
    return;
  }
  const float a = (lo - offset) / slope, b = (hi - offset) / slope, perRow = -rowSlope / slope;
  setup.lo[which] = std::min(a, b), setup.hi[which] = std::max(a, b);
  setup.loSlope[which] = setup.hiSlope[which] = perRow;
}

Setup setupOf(const rain::StreakInstance& streak, const rain::ShadingParams& shading,
              const std::array<float, 4>& rect, int width, int height) {
  const StreakQuad quad = StreakQuad::of(streak);
  Setup setup;
  setup.headPixelX = static_cast<int>(std::floor(quad.headX));
  setup.headOffsetX = static_cast<float>(setup.headPixelX) + 0.5f - quad.headX;
  setup.headY = quad.headY;
  setup.axisX = quad.axisX, setup.axisY = quad.axisY;
  setup.halfWidth = 0.5f * quad.widthPx;
  setup.inverseWidth = 1.0f / quad.widthPx;
  setup.inverseLengthPlusWidth = 1.0f / (quad.lengthPx + quad.widthPx);
  // across = (cx - headX) * -axisY + (cy - headY) * axisX in [-width / 2, width / 2];
  // along = (cx - headX) * axisX + (cy - headY) * axisY in [-width / 2, length + width / 2].
  boundCentres(quad.headX * quad.axisY - quad.headY * quad.axisX, -quad.axisY, quad.axisX,
               -setup.halfWidth, setup.halfWidth, setup, 0);
  boundCentres(-quad.headX * quad.axisX - quad.headY * quad.axisY, quad.axisX, quad.axisY,
               -setup.halfWidth, quad.lengthPx + setup.halfWidth, setup, 1);
  setup.alpha = streak.alpha;
  setup.depthMeters = streak.depthMeters;
  // Texel coordinates with centres on integers, shifted by the one-texel border.
  setup.rectX0 = rect[0] - 0.5f + 1.0f, setup.rectY0 = rect[1] - 0.5f + 1.0f;
  setup.rectWidth = rect[2] - rect[0], setup.rectHeight = rect[3] - rect[1];
  setup.radiance = streakRadiance(shading, streak);
  setup.local = {streak.localR, streak.localG, streak.localB};
  setup.beadCycles = streak.beadCycles;
  setup.beadPhase = streak.beadPhase;
  setup.glintMode20 = streak.glintMode20;
  setup.glintMode31 = streak.glintMode31;
  setup.hasLocal = streak.localR > 0.0f || streak.localG > 0.0f || streak.localB > 0.0f;
  boundingPixels(quad, width, height, setup);
  return setup;
}

}  // namespace

void StreakRasterCpu::setStrokeAtlas(const rain::StrokeAtlas& atlas) {
  validateAtlas(atlas);
  paddedWidth_ = atlas.width + 2;
  paddedHeight_ = atlas.height + 2;
  // Texel (x, y) of the padded atlas is texel (x - 1, y - 1) of the atlas, clamped to its edge.
  auto texel = [&](int x, int y) {
    const int sx = std::clamp(x - 1, 0, atlas.width - 1),
              sy = std::clamp(y - 1, 0, atlas.height - 1);
    return atlas.alpha[static_cast<size_t>(sy) * atlas.width + sx];
  };
  quads_.resize(static_cast<size_t>(paddedWidth_) * paddedHeight_ * 4);
  for (int y = 0; y < paddedHeight_; ++y) {
    for (int x = 0; x < paddedWidth_; ++x) {
      float* quad = quads_.data() + (static_cast<size_t>(y) * paddedWidth_ + x) * 4;
      const int right = std::min(x + 1, paddedWidth_ - 1),
                down = std::min(y + 1, paddedHeight_ - 1);
      quad[0] = texel(x, y), quad[1] = texel(right, y);
      quad[2] = texel(x, down), quad[3] = texel(right, down);
    }
  }
  rects_ = atlas.rects;
}

void StreakRasterCpu::render(Image& frame, const std::vector<rain::StreakInstance>& streaks,
                             const rain::ShadingParams& shading, FarDropLines* farLines,
                             const std::vector<rain::StreakInstance>* farStreaks) {
  const int width = frame.width, height = frame.height;
  const size_t count = streaks.size();
  const int tilesX = (width + kTilePx - 1) / kTilePx, tilesY = (height + kTilePx - 1) / kTilePx;
  const size_t tiles = static_cast<size_t>(tilesX) * static_cast<size_t>(tilesY);
  auto forEachTile = [&](const Setup& s, auto&& visit) {
    if (s.x0 > s.x1 || s.y0 > s.y1) return;
    for (int ty = s.y0 / kTilePx; ty <= s.y1 / kTilePx; ++ty) {
      for (int tx = s.x0 / kTilePx; tx <= s.x1 / kTilePx; ++tx) {
        visit(static_cast<size_t>(ty) * tilesX + tx);
      }
    }
  };

  // Bin the streaks to tiles in drawing order: a counting sort by tile, in parallel over chunks
  // of streaks (chunk k's streaks of a tile follow chunk k - 1's). Each tile gets its own copies:
  // a tile then reads its streaks in sequence instead of hopping over all of them.
  const size_t chunks = std::clamp<size_t>(count / kStreaksPerChunk, 1, kMaxChunks);
  const size_t perChunk = (count + chunks - 1) / chunks;
  setups_.resize(count);
  chunkCounts_.assign(chunks * tiles, 0);
  forEachIndex(chunks, [&](size_t chunk) {
    size_t* counts = chunkCounts_.data() + chunk * tiles;
    for (size_t i = chunk * perChunk; i < std::min(count, (chunk + 1) * perChunk); ++i) {
      const auto& rect = rects_[static_cast<size_t>(streaks[i].strokeIndex)];
      setups_[i] = setupOf(streaks[i], shading, rect, width, height);
      forEachTile(setups_[i], [&](size_t t) { ++counts[t]; });
    }
  });
  // Where each chunk's streaks of each tile start; tileStart_ where each tile's do.
  tileStart_.assign(tiles + 1, 0);
  size_t position = 0;
  for (size_t t = 0; t < tiles; ++t) {
    tileStart_[t] = position;
    for (size_t chunk = 0; chunk < chunks; ++chunk) {
      const size_t n = chunkCounts_[chunk * tiles + t];
      chunkCounts_[chunk * tiles + t] = position;
      position += n;
    }
  }
  tileStart_[tiles] = position;
  binned_.resize(position);
  forEachIndex(chunks, [&](size_t chunk) {
    size_t* next = chunkCounts_.data() + chunk * tiles;
    for (size_t i = chunk * perChunk; i < std::min(count, (chunk + 1) * perChunk); ++i) {
      forEachTile(setups_[i], [&](size_t t) { binned_[next[t]++] = setups_[i]; });
    }
  });

  const std::vector<float>* depth = frame.findPlane(kDepthPlane);
  // A frame from the reader has no rain planes: made now, they hold zeros already.
  const bool fresh = std::none_of(kRainPlaneNames.begin(), kRainPlaneNames.end(),
                                  [&](const char* name) { return frame.findPlane(name); });
  const RainPlanes planes = rainPlanesOf(frame);
  const TileTarget target{planes.r, planes.g, planes.b, planes.a, depth ? depth->data() : nullptr,
                          width,    fresh};
  const bool lined = farLines && farStreaks && !farStreaks->empty();
  if (lined) {
    // The lines go under every streak: drawn over the whole cleared layer first.
    if (!fresh) {
      for (float* plane : {planes.r, planes.g, planes.b, planes.a}) {
        std::fill_n(plane, frame.pixelCount(), 0.0f);
      }
    }
    farLines->draw(*farStreaks, shading,
                   {planes.r, planes.g, planes.b, planes.a, target.depth, width, height});
  }
  const PaddedAtlas atlas{quads_.data(), paddedWidth_};
  forEachBlock(tiles, 1, [&](size_t begin, size_t end) {
    for (size_t t = begin; t != end; ++t) {
      const int tx0 = static_cast<int>(t % tilesX) * kTilePx;
      const int ty0 = static_cast<int>(t / tilesX) * kTilePx;
      const int tx1 = std::min(tx0 + kTilePx, width) - 1;
      const int ty1 = std::min(ty0 + kTilePx, height) - 1;
      TileTarget tile = target;
      tile.cleared = target.cleared || lined;
      drawTile(binned_.data() + tileStart_[t], tileStart_[t + 1] - tileStart_[t], atlas, tile, tx0,
               ty0, tx1, ty1, portableOnly_);
      // The tile's layer is still in cache: finish Eq. 2 on it now.
      for (int y = ty0; y <= ty1; ++y) {
        compositeRainPixels(shading.backgroundWeight, planes,
                            static_cast<size_t>(y) * width + static_cast<size_t>(tx0),
                            static_cast<size_t>(tx1 - tx0 + 1));
      }
    }
  });
}

}  // namespace pluvia::gpu
