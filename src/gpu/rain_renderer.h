#pragma once
// GPU rain insertion through headless EGL. This header exposes no GL or EGL type: everything
// GL lives in src/gpu/*.cpp. One RainRenderer owns one EGL context and must be used from the
// thread that created it.
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
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "image/equirect.h"
#include "image/image.h"

namespace pluvia::gpu {

// One streak, 12 floats (laid out for the shaders' streak storage buffer, std430).
struct StreakInstance {
  float headX, headY, tailX, tailY;  // pixels; origin at the top-left corner, y down
  float widthPx, alpha, depthMeters, strokeIndex;
  float viewX, viewY, viewZ, padding;  // unit direction camera -> drop (world space)
};
static_assert(sizeof(StreakInstance) == 12 * sizeof(float));

// The quad of a streak: it spans from head to tail along its axis, extended by widthPx / 2 at
// both ends, and widthPx across. Matte coordinates: u across (0 left edge .. 1 right edge when
// looking from head to tail), v along (0 at head end .. 1 at tail end).

// Stroke mattes packed in one single-channel float atlas.
struct StrokeAtlas {
  int width = 0;
  int height = 0;
  std::vector<float> alpha;                 // width * height, row 0 at the top
  std::vector<std::array<float, 4>> rects;  // per stroke: x0, y0, x1, y1 in atlas pixels
};

// Shading inputs: the two terms of C (see above), at least one of them present, and c.
// SH term: real SH of order L = shOrder <= 3 ((L+1)^2 coefficients, index l*l + l + m), basis as
// in shaders/common_sh.glsl and its CPU twin shEvaluate(); used only when envSh is non-empty.
// Map term: per view direction, the radiance a drop shows (the environment already convolved
// with the drop's transfer); used only when radianceMap is non-empty. A map is meant to be
// small (128 x 64, say) and to change per clip, not per frame: render() compares it with the
// one on the GPU and uploads it only when it differs.
struct ShadingParams {
  int shOrder = 0;
  std::vector<std::array<float, 3>> envSh;  // (shOrder+1)^2 RGB coefficients; empty: no SH term
  std::vector<float> transferZonal;         // shOrder+1 values: rotated zonal transfer (see above)
  EquirectMap radianceMap;                  // empty: no map term
  float backgroundWeight = 0.0f;            // c in C' = C + c*B
};

// Evaluates the real SH basis up to order 3 at unit direction (x, y, z): 16 values.
std::array<float, 16> shEvaluate(float x, float y, float z);

class RainRenderer {
 public:
  // Creates the headless EGL context and the render targets. Throws pluvia::Error with the EGL
  // error when no context can be made.
  RainRenderer(int width, int height);
  ~RainRenderer();
  RainRenderer(const RainRenderer&) = delete;
  RainRenderer& operator=(const RainRenderer&) = delete;

  void setStrokeAtlas(const StrokeAtlas& atlas);

  // Draws the streaks over `frame` (its RGBA is the background B; its "depth" plane, if any, the
  // scene depth; no plane means infinitely far). On return frame.rgba holds the composite and
  // planes "rain.R", "rain.G", "rain.B", "rain.A" hold the premultiplied rain layer alone (rain
  // over transparent black), "matte" = rain.A. Throws pluvia::Error (stage "rain") on
  // inconsistent inputs, shading included.
  void render(Image& frame, const std::vector<StreakInstance>& streaks,
              const ShadingParams& shading);

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
void renderRainCpu(Image& frame, const std::vector<StreakInstance>& streaks,
                   const ShadingParams& shading, const StrokeAtlas& atlas);

}  // namespace pluvia::gpu
