// renderRainCpu: RainRenderer::render evaluated on the CPU at pixel centres, for tests on tiny
// targets. Every step mirrors the GPU path: the quad frame and matte coordinates of the
// shaders (streak_quad.h), GL_LINEAR + CLAMP_TO_EDGE sampling of the atlas, the depth test and
// the two blend equations, all in float and in the drawing order of
// streak_batches.h.
#include <algorithm>
#include <cmath>

#include "gpu/rain_inputs.h"
#include "gpu/rain_renderer.h"
#include "gpu/streak_batches.h"
#include "gpu/streak_quad.h"
#include "gpu/streak_radiance.h"

namespace pluvia::gpu {
namespace {

// What a GL sampler does for GL_LINEAR with CLAMP_TO_EDGE at normalised coordinates (s, t):
// texel centres at +0.5, both neighbours clamped into the texture, lerps as v0 + f * (v1 - v0).
float sampleLinearClampToEdge(const rain::StrokeAtlas& atlas, float s, float t) {
  const float x = s * static_cast<float>(atlas.width) - 0.5f;
  const float y = t * static_cast<float>(atlas.height) - 0.5f;
  const float x0 = std::floor(x);
  const float y0 = std::floor(y);
  const float fx = x - x0;
  const float fy = y - y0;
  auto texel = [&](float tx, float ty) {
    const int ix = std::clamp(static_cast<int>(tx), 0, atlas.width - 1);
    const int iy = std::clamp(static_cast<int>(ty), 0, atlas.height - 1);
    return atlas.alpha[static_cast<size_t>(iy) * atlas.width + ix];
  };
  const float a00 = texel(x0, y0), a10 = texel(x0 + 1.0f, y0);
  const float a01 = texel(x0, y0 + 1.0f), a11 = texel(x0 + 1.0f, y0 + 1.0f);
  const float top = a00 + fx * (a10 - a00);
  const float bottom = a01 + fx * (a11 - a01);
  return top + fy * (bottom - top);
}

struct PixelRange {
  int x0, y0, x1, y1;  // inclusive
};

// Pixels whose centres may lie on the quad: its bounding box, one pixel wider for rounding.
PixelRange candidatePixels(const StreakQuad& quad, int width, int height) {
  float minX, minY, maxX, maxY;
  quad.bounds(minX, minY, maxX, maxY);
  auto clampTo = [](float value, int size) {
    return static_cast<int>(std::clamp(value, -1.0f, static_cast<float>(size)));
  };
  return {std::max(clampTo(std::floor(minX) - 1.0f, width), 0),
          std::max(clampTo(std::floor(minY) - 1.0f, height), 0),
          std::min(clampTo(std::ceil(maxX) + 1.0f, width), width - 1),
          std::min(clampTo(std::ceil(maxY) + 1.0f, height), height - 1)};
}

}  // namespace

void renderRainCpu(Image& frame, const std::vector<rain::StreakInstance>& streaks,
                   const rain::ShadingParams& shading, const rain::StrokeAtlas& atlas) {
  validateFrame(frame);
  validateShading(shading);
  if (!streaks.empty()) validateAtlas(atlas);
  validateStreaks(streaks, static_cast<int>(atlas.rects.size()));

  std::vector<float> rain(frame.pixelCount() * 4, 0.0f);
  std::vector<float> sceneDepth;
  comparableSceneDepth(frame, sceneDepth);
  const std::vector<float> background = frame.rgba;  // B stays the input, not the composite
  const float atlasWidth = static_cast<float>(atlas.width);
  const float atlasHeight = static_cast<float>(atlas.height);

  for (const rain::StreakInstance& streak : orderForDrawing(streaks).streaks) {
    const StreakQuad quad = StreakQuad::of(streak);
    const std::array<float, 3> radiance = streakRadiance(shading, streak);
    const std::array<float, 4>& rect = atlas.rects[static_cast<size_t>(streak.strokeIndex)];
    const PixelRange range = candidatePixels(quad, frame.width, frame.height);
    for (int y = range.y0; y <= range.y1; ++y) {
      for (int x = range.x0; x <= range.x1; ++x) {
        float u, v;
        quad.matteCoordinates(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f, u, v);
        if (u < 0.0f || u > 1.0f || v < 0.0f || v > 1.0f) continue;
        const size_t pixel = static_cast<size_t>(y) * frame.width + x;
        if (streak.depthMeters > sceneDepth[pixel]) continue;
        const float atlasX = rect[0] + u * (rect[2] - rect[0]);
        const float atlasY = rect[1] + v * (rect[3] - rect[1]);
        const float matte =
            sampleLinearClampToEdge(atlas, atlasX / atlasWidth, atlasY / atlasHeight);
        const float alpha = std::clamp(matte * streak.alpha, 0.0f, 1.0f);
        if (alpha <= 0.0f) continue;
        float* composite = frame.rgba.data() + pixel * 4;
        float* layer = rain.data() + pixel * 4;
        const float bead = rain::localLightBead(streak.beadCycles, streak.beadPhase,
                                                streak.glintMode20, streak.glintMode31, v);
        const std::array<float, 3> local{streak.localR, streak.localG, streak.localB};
        for (int c = 0; c < 3; ++c) {
          const float shaded =
              radiance[c] + bead * local[c] + shading.backgroundWeight * background[pixel * 4 + c];
          // Attachment 0: (SRC_ALPHA, ONE_MINUS_SRC_ALPHA) on RGB, alpha kept.
          composite[c] = shaded * alpha + composite[c] * (1.0f - alpha);
          // Attachment 1: premultiplied source, (ONE, ONE_MINUS_SRC_ALPHA).
          layer[c] = alpha * shaded + layer[c] * (1.0f - alpha);
        }
        layer[3] = alpha + layer[3] * (1.0f - alpha);
      }
    }
  }
  storeRainLayer(rain, frame);
}

}  // namespace pluvia::gpu
