#include "gpu/rain_inputs.h"

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>

#include <fmt/format.h>

#include "gpu/rain_error.h"
#include "util/parallel.h"

namespace pluvia::gpu {

namespace {

// Runs body(first, end) over the frame's pixels in blocks on every core: the per-pixel passes
// around the GPU's draw are the fixed cost of a frame, and on a GPU they are most of it.
template <class Body>
void forEachPixelBlock(size_t pixels, const Body& body) {
  constexpr size_t kBlockPixels = 16384;
  forEachBlock(pixels, kBlockPixels, body);
}

}  // namespace

void validateFrame(const Image& frame) {
  if (frame.empty()) throwRainError("cannot draw rain on an empty frame");
  if (frame.rgba.size() != frame.pixelCount() * 4) {
    throwRainError(fmt::format("frame of {}x{} pixels holds {} RGBA floats instead of {}",
                               frame.width, frame.height, frame.rgba.size(),
                               frame.pixelCount() * 4));
  }
  const std::vector<float>* depth = frame.findPlane(kDepthPlane);
  if (depth && depth->size() != frame.pixelCount()) {
    throwRainError(fmt::format("depth plane holds {} values for {}x{} pixels", depth->size(),
                               frame.width, frame.height));
  }
}

namespace {

void validateShTerm(const rain::ShadingParams& shading) {
  if (shading.shOrder < 0 || shading.shOrder > 3) {
    throwRainError(fmt::format("SH order {} is outside 0..3", shading.shOrder));
  }
  const size_t coefficients = static_cast<size_t>((shading.shOrder + 1) * (shading.shOrder + 1));
  if (shading.envSh.size() != coefficients) {
    throwRainError(fmt::format("SH order {} needs {} environment coefficients, got {}",
                               shading.shOrder, coefficients, shading.envSh.size()));
  }
  if (shading.transferZonal.size() != static_cast<size_t>(shading.shOrder + 1)) {
    throwRainError(fmt::format("SH order {} needs {} zonal transfer values, got {}",
                               shading.shOrder, shading.shOrder + 1, shading.transferZonal.size()));
  }
}

// An empty map (no map term) must hold no data either: data with a zero size is a mistake.
void validateRadianceMap(const EquirectMap& map) {
  if (map.empty()) {
    if (!map.rgb.empty()) {
      throwRainError(fmt::format("radiance map of {}x{} texels holds {} floats", map.width,
                                 map.height, map.rgb.size()));
    }
    return;
  }
  const size_t expected = static_cast<size_t>(map.width) * static_cast<size_t>(map.height) * 3;
  if (map.rgb.size() != expected) {
    throwRainError(fmt::format("radiance map of {}x{} texels holds {} floats instead of {} (RGB)",
                               map.width, map.height, map.rgb.size(), expected));
  }
  const auto bad = std::find_if(map.rgb.begin(), map.rgb.end(),
                                [](float value) { return !std::isfinite(value); });
  if (bad != map.rgb.end()) {
    const size_t index = static_cast<size_t>(bad - map.rgb.begin());
    const size_t texel = index / 3;
    throwRainError(fmt::format("radiance map texel ({}, {}) has a non-finite {} value ({})",
                               texel % map.width, texel / map.width, "RGB"[index % 3], *bad));
  }
}

}  // namespace

void validateShading(const rain::ShadingParams& shading) {
  validateRadianceMap(shading.radianceMap);
  const bool hasSh = !shading.envSh.empty();
  if (!hasSh && shading.radianceMap.empty()) {
    throwRainError(
        "shading has neither SH environment coefficients nor a radiance map: set at least one");
  }
  if (hasSh) validateShTerm(shading);
}

void validateAtlas(const rain::StrokeAtlas& atlas) {
  if (atlas.width <= 0 || atlas.height <= 0) {
    throwRainError(fmt::format("stroke atlas has no pixels ({}x{})", atlas.width, atlas.height));
  }
  if (atlas.alpha.size() != static_cast<size_t>(atlas.width) * atlas.height) {
    throwRainError(fmt::format("stroke atlas of {}x{} pixels holds {} values", atlas.width,
                               atlas.height, atlas.alpha.size()));
  }
}

void validateStreaks(const std::vector<rain::StreakInstance>& streaks, int strokeCount) {
  if (!streaks.empty() && strokeCount == 0) {
    throwRainError("streaks to draw but no strokes: set a stroke atlas with strokes first");
  }
  for (size_t i = 0; i < streaks.size(); ++i) {
    const rain::StreakInstance& streak = streaks[i];
    if (!std::isfinite(streak.headX) || !std::isfinite(streak.headY) ||
        !std::isfinite(streak.tailX) || !std::isfinite(streak.tailY)) {
      throwRainError(fmt::format("streak {} has a non-finite end point", i));
    }
    // The local lights' term enters C as it is: finite and >= 0, and its beads finite (a huge
    // cycle count would lose the phase in float, so it is bounded).
    if (!(streak.localR >= 0.0f && streak.localR <= FLT_MAX && streak.localG >= 0.0f &&
          streak.localG <= FLT_MAX && streak.localB >= 0.0f && streak.localB <= FLT_MAX)) {
      throwRainError(
          fmt::format("streak {} has local-light radiance ({}, {}, {}): not finite and >= 0", i,
                      streak.localR, streak.localG, streak.localB));
    }
    if (!(std::abs(streak.beadCycles) <= 1e4f && std::abs(streak.beadPhase) <= 1e4f)) {
      throwRainError(fmt::format("streak {} has bead cycles {} and phase {}: not within +/-1e4", i,
                                 streak.beadCycles, streak.beadPhase));
    }
    if (!(std::abs(streak.glintMode20) <= 1e4f && std::abs(streak.glintMode31) <= 1e4f)) {
      throwRainError(fmt::format("streak {} has glint modes {} and {}: not within +/-1e4", i,
                                 streak.glintMode20, streak.glintMode31));
    }
    const float index = streak.strokeIndex;
    // Both renderers truncate the index to an integer, as GLSL's int() does; for index >= 0
    // that stays below the count exactly when the float does.
    if (!(index >= 0.0f && index < static_cast<float>(strokeCount))) {
      throwRainError(fmt::format("streak {} uses stroke {} but the atlas has {} strokes", i, index,
                                 strokeCount));
    }
  }
}

void comparableSceneDepth(const Image& frame, std::vector<float>& depthMeters) {
  depthMeters.resize(frame.pixelCount());
  const std::vector<float>* depth = frame.findPlane(kDepthPlane);
  forEachPixelBlock(frame.pixelCount(), [&](size_t first, size_t end) {
    for (size_t i = first; i < end; ++i) {
      depthMeters[i] = depth && std::isfinite((*depth)[i]) ? (*depth)[i] : kFarDepthMeters;
    }
  });
}

void storeRainLayer(const std::vector<float>& rainRgba, Image& frame) {
  std::vector<float>* channels[4] = {&frame.plane("rain.R"), &frame.plane("rain.G"),
                                     &frame.plane("rain.B"), &frame.plane("rain.A")};
  for (size_t i = 0; i < frame.pixelCount(); ++i) {
    for (int c = 0; c < 4; ++c) (*channels[c])[i] = rainRgba[i * 4 + c];
  }
  frame.planes["matte"] = *channels[3];
}

void compositeRainLayer(const std::vector<float>& radianceLayer, float backgroundWeight,
                        Image& frame) {
  float* planes[5] = {frame.plane("rain.R").data(), frame.plane("rain.G").data(),
                      frame.plane("rain.B").data(), frame.plane("rain.A").data(),
                      frame.plane("matte").data()};
  const float c = backgroundWeight;
  forEachPixelBlock(frame.pixelCount(), [&](size_t first, size_t end) {
    for (size_t i = first; i < end; ++i) {
      const float* layer = radianceLayer.data() + i * 4;
      float* background = frame.rgba.data() + i * 4;
      const float coverage = layer[3];
      for (int ch = 0; ch < 3; ++ch) {
        // c = 0 (the default shading) adds nothing, not even 0 * an infinite background.
        const float rain = c == 0.0f ? layer[ch] : layer[ch] + c * background[ch] * coverage;
        planes[ch][i] = rain;
        if (coverage != 0.0f || rain != 0.0f) {
          background[ch] = rain + (1.0f - coverage) * background[ch];
        }
      }
      planes[3][i] = coverage;
      planes[4][i] = coverage;
    }
  });
}
namespace {

// Whether every bit of the layer is zero over pixels [first, first + count) and, when c enters,
// every background value there is finite: then compositing leaves rgba and the rain planes as
// they are (rain = 0 + c * B * 0 = 0, composite = B).
bool layerIsEmpty(const RainPlanes& planes, bool backgroundEnters, size_t first, size_t count) {
  uint32_t bits = 0;
  for (size_t i = first; i < first + count; ++i) {
    bits |= std::bit_cast<uint32_t>(planes.a[i]) | std::bit_cast<uint32_t>(planes.r[i]) |
            std::bit_cast<uint32_t>(planes.g[i]) | std::bit_cast<uint32_t>(planes.b[i]);
  }
  if (bits != 0) return false;
  if (!backgroundEnters) return true;
  bool finite = true;
  for (size_t i = first * 4; i < (first + count) * 4; ++i) finite &= std::isfinite(planes.rgba[i]);
  return finite;
}

}  // namespace

void compositeRainPixels(float backgroundWeight, const RainPlanes& planes, size_t first,
                         size_t count) {
  const float c = backgroundWeight;
  // Runs of pixels without rain (most of a frame) only get their matte.
  constexpr size_t kRun = 16;
  for (size_t start = first; start < first + count; start += kRun) {
    const size_t end = std::min(start + kRun, first + count);
    if (layerIsEmpty(planes, c != 0.0f, start, end - start)) {
      std::fill(planes.matte + start, planes.matte + end, 0.0f);
      continue;
    }
    if (c == 0.0f) {
      // The default shading: no c * B term, and a pixel without rain keeps B exactly.
      for (size_t i = start; i < end; ++i) {
        float* background = planes.rgba + i * 4;
        const float keep = 1.0f - planes.a[i];
        background[0] = planes.r[i] + keep * background[0];
        background[1] = planes.g[i] + keep * background[1];
        background[2] = planes.b[i] + keep * background[2];
        planes.matte[i] = planes.a[i];
      }
      continue;
    }
    for (size_t i = start; i < end; ++i) {
      float* background = planes.rgba + i * 4;
      const float coverage = planes.a[i];
      float* rgb[3] = {planes.r + i, planes.g + i, planes.b + i};
      for (int ch = 0; ch < 3; ++ch) {
        // As compositeRainLayer: c = 0 adds nothing, not even 0 * an infinite background.
        const float rain = c == 0.0f ? *rgb[ch] : *rgb[ch] + c * background[ch] * coverage;
        *rgb[ch] = rain;
        if (coverage != 0.0f || rain != 0.0f) {
          background[ch] = rain + (1.0f - coverage) * background[ch];
        }
      }
      planes.matte[i] = coverage;
    }
  }
}

RainPlanes rainPlanesOf(Image& frame) {
  return {frame.rgba.data(),
          frame.plane("rain.R").data(),
          frame.plane("rain.G").data(),
          frame.plane("rain.B").data(),
          frame.plane("rain.A").data(),
          frame.plane("matte").data()};
}

void clearRainLayer(Image& frame) {
  for (const char* name : {"rain.R", "rain.G", "rain.B", "rain.A", "matte"}) {
    frame.plane(name).assign(frame.pixelCount(), 0.0f);
  }
}

}  // namespace pluvia::gpu
