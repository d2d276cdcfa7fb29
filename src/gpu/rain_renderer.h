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
#include <optional>
#include <string>
#include <vector>

#include "image/image.h"
#include "rain/streak_types.h"

namespace pluvia::gpu {

// Who draws the streaks. Egl: the GL pipeline above, on whatever device EGL finds (a GPU, or
// Mesa's llvmpipe). Cpu: StreakRasterCpu (streak_raster_cpu.h), a rasteriser made for streaks,
// the same pictures within the tolerance tests/gpu/test_streak_raster_cpu.cpp states, several
// times faster than llvmpipe. Auto: the default backend when one is set (setRainBackend), else
// EGL on a hardware device and the CPU rasteriser when the device is a software one (llvmpipe,
// softpipe, swrast, SwiftShader) or when EGL has no device at all.
enum class RainBackend { Auto, Egl, Cpu };

// The backend of that name ("auto", "egl", "cpu", any case); none for any other.
std::optional<RainBackend> rainBackendNamed(const std::string& name);
// What a renderer asked for Auto uses (the front end sets it from $PLUVIA_RAIN_BACKEND,
// cli/process_variables.h, before any work); Auto: the device decides.
void setRainBackend(RainBackend backend);

// True for GL renderer strings of software rasterisers ("llvmpipe (LLVM 15.0.6, 256 bits)").
bool isSoftwareGlRenderer(const std::string& rendererDescription);

class RainRenderer {
 public:
  // Chooses the backend (see RainBackend; the choice is logged) and makes its resources: for
  // EGL the headless context and the render targets. Throws pluvia::Error with the EGL error
  // when an EGL renderer is asked for and no context can be made.
  RainRenderer(int width, int height, RainBackend backend = RainBackend::Auto);
  ~RainRenderer();
  RainRenderer(const RainRenderer&) = delete;
  RainRenderer& operator=(const RainRenderer&) = delete;

  void setStrokeAtlas(const rain::StrokeAtlas& atlas);

  // Draws the streaks over `frame` (its RGBA is the background B; its "depth" plane, if any, the
  // scene depth; no plane means infinitely far). On return frame.rgba holds the composite and
  // planes "rain.R", "rain.G", "rain.B", "rain.A" hold the premultiplied rain layer alone (rain
  // over transparent black), "matte" = rain.A. Throws pluvia::Error (stage "rain") on
  // inconsistent inputs, shading included.
  // farStreaks: drawn as single-pixel lines under the streaks (far_drop_lines.h), not as quads;
  // empty (the default), and the frame is exactly what drawing `streaks` alone gives.
  void render(Image& frame, const std::vector<rain::StreakInstance>& streaks,
              const rain::ShadingParams& shading,
              const std::vector<rain::StreakInstance>& farStreaks = {});

  // "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 ...", "NVIDIA H100 ...", or "CPU streak
  // rasteriser (2 threads; ...)".
  std::string deviceDescription() const;
  // The backend chosen: Egl or Cpu, never Auto.
  RainBackend backend() const;

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
