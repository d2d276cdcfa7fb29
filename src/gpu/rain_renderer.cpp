// RainRenderer: one headless GL context and the GPU resources of one frame size, reused for
// every frame (re-made only when the size changes), so a long clip holds steady memory.
#include "gpu/rain_renderer.h"

#include <optional>

#include <epoxy/gl.h>

#include "gpu/egl_context.h"
#include "gpu/frame_targets.h"
#include "gpu/gl_check.h"
#include "gpu/gpu_stroke_atlas.h"
#include "gpu/rain_inputs.h"
#include "gpu/rain_program.h"
#include "gpu/streak_stream.h"

namespace pluvia::gpu {

struct RainRenderer::Impl {
  // Declared first so it is destroyed last, after every GL object below.
  HeadlessGlContext context;
  RainProgram program;
  StreakStream streaks;
  GpuStrokeAtlas atlas;
  std::optional<FrameTargets> targets;
  std::vector<float> sceneDepth;  // scratch, kept to avoid a per-frame allocation
  std::vector<float> rainRgba;    // scratch for the read-back rain layer

  // GL objects are deleted by the members' destructors; they need this context current.
  ~Impl() { context.makeCurrent(); }

  void ensureTargets(int width, int height) {
    if (!targets || targets->width() != width || targets->height() != height) {
      targets.reset();  // free the old size first: two 4K target sets need not coexist
      targets.emplace(width, height);
    }
  }
};

RainRenderer::RainRenderer(int width, int height) : impl_(std::make_unique<Impl>()) {
  impl_->ensureTargets(width, height);
}

RainRenderer::~RainRenderer() = default;

void RainRenderer::setStrokeAtlas(const StrokeAtlas& atlas) {
  impl_->context.makeCurrent();
  impl_->atlas.upload(atlas);
}

void RainRenderer::render(Image& frame, const std::vector<StreakInstance>& streaks,
                          const ShadingParams& shading) {
  validateFrame(frame);
  validateShading(shading);
  validateStreaks(streaks, impl_->atlas.strokeCount());
  if (streaks.empty()) {
    clearRainLayer(frame);
    return;
  }
  Impl& gpu = *impl_;
  gpu.context.makeCurrent();
  gpu.ensureTargets(frame.width, frame.height);
  comparableSceneDepth(frame, gpu.sceneDepth);
  gpu.targets->begin(frame.rgba, gpu.sceneDepth);
  gpu.streaks.upload(streaks);
  gpu.program.use(shading, frame.width, frame.height, gpu.atlas.width(), gpu.atlas.height());
  gpu.atlas.bind(kAtlasUnit, kStrokeRectBinding);
  gpu.targets->bindInputs(kBackgroundUnit, kSceneDepthUnit);
  gpu.streaks.draw();

  // Blending with (ZERO, ONE) on alpha keeps the background's alpha exactly, so the composite
  // is read straight into the frame.
  gpu.targets->readComposite(frame.rgba.data());
  gpu.rainRgba.resize(frame.pixelCount() * 4);
  gpu.targets->readRainLayer(gpu.rainRgba.data());
  storeRainLayer(gpu.rainRgba, frame);
}

std::string RainRenderer::deviceDescription() const {
  impl_->context.makeCurrent();
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return std::string(renderer ? renderer : "unknown renderer") + ", OpenGL " +
         (version ? version : "unknown version");
}

}  // namespace pluvia::gpu
