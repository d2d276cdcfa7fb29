#pragma once
// GPU rain insertion through headless EGL. This header exposes no GL or EGL type: everything
// GL lives in src/gpu/*.cpp. One RainRenderer owns one EGL context and must be used from the
// thread that created it. What it draws comes as rain/streak_types.h: streaks, the stroke
// atlas, the shading inputs.
//
// What it draws: one screen-space quad per streak (instanced), textured with a stroke matte
// from the atlas, depth-tested against the scene's "depth" plane, shaded with the drop's
// precomputed radiance and composited over the background as in Wang et al. (Eq. 2):
//   C_sh  = max(sum_l zonal[l] * sum_m Y_lm(view) * envSh[l,m], 0)   (SH transfer, PRT)
//   C_map = radianceMap(view)               (bilinear, as sampleEquirect() in image/equirect.h)
//   C  = C_sh + C_map         (per streak, RGB; each term only when its input is present)
//   C' = C + c * B                                            (B: background pixel)
//   out = alpha * C' + (1 - alpha) * dst                      (drawn in instance order)
// alpha = matte(u, v) * streak.alpha, and the fragment is dropped when the streak lies behind
// the scene (streak.depthMeters > depth plane at that pixel).
// Evaluation order (same maths, not the same float operations): the GPU blends only
// L = (alpha * C, alpha) premultiplied over transparent black; with A = L.alpha the CPU then
// sets rain = L.rgb + c * B * A and out = rain + (1 - A) * B, which expands to the two lines
// above because sum_i alpha_i * prod_{j>i} (1 - alpha_j) = A. So B never goes to the GPU.
#include <memory>
#include <string>
#include <vector>

#include "image/image.h"
#include "rain/streak_types.h"

namespace pluvia::gpu {

class RainRenderer {
 public:
  // Creates the headless EGL context and the render targets. Throws pluvia::Error with the EGL
  // error when no context can be made.
  RainRenderer(int width, int height);
  ~RainRenderer();
  RainRenderer(const RainRenderer&) = delete;
  RainRenderer& operator=(const RainRenderer&) = delete;

  void setStrokeAtlas(const rain::StrokeAtlas& atlas);

  // Draws the streaks over `frame` (its RGBA is the background B; its "depth" plane, if any, the
  // scene depth; no plane means infinitely far). On return frame.rgba holds the composite and
  // planes "rain.R", "rain.G", "rain.B", "rain.A" hold the premultiplied rain layer alone (rain
  // over transparent black), "matte" = rain.A. Throws pluvia::Error (stage "rain") on
  // inconsistent inputs, shading included.
  void render(Image& frame, const std::vector<rain::StreakInstance>& streaks,
              const rain::ShadingParams& shading);

  // "llvmpipe (LLVM 15.0.6, 256 bits)", "NVIDIA H100 ..."
  std::string deviceDescription() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The CPU twin of RainRenderer::render: the same maths, evaluated at pixel centres, for tests
// on tiny targets. It blends C' streak by streak as written above (not in the GPU's order), so
// the tests also check the reordering. Bilinear matte sampling with clamp-to-edge, as the GPU's
// sampler.
void renderRainCpu(Image& frame, const std::vector<rain::StreakInstance>& streaks,
                   const rain::ShadingParams& shading, const rain::StrokeAtlas& atlas);

}  // namespace pluvia::gpu
