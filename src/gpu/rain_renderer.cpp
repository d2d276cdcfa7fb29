// RainRenderer: one headless GL context and the GPU resources of one frame size, reused for
// every frame (re-made only when the size changes), so a long clip holds steady memory.
#include "gpu/rain_renderer.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdlib>
#include <optional>

#include <epoxy/gl.h>
#include <fmt/format.h>
#include <tbb/info.h>

#include "gpu/egl_context.h"
#include "gpu/far_drop_lines.h"
#include "gpu/frame_targets.h"
#include "gpu/gl_check.h"
#include "gpu/gpu_radiance_map.h"
#include "gpu/gpu_stroke_atlas.h"
#include "gpu/rain_error.h"
#include "gpu/rain_inputs.h"
#include "gpu/rain_program.h"
#include "gpu/streak_batches.h"
#include "gpu/streak_raster_cpu.h"
#include "gpu/streak_stream.h"
#include "util/error.h"
#include "util/log.h"

namespace pluvia::gpu {

namespace {

// Every GL object of a renderer, boxed so that it can be abandoned rather than deleted (see
// ~Impl).
struct GpuObjects {
  RainProgram program;
  StreakStream streaks;
  GpuStrokeAtlas atlas;
  GpuRadianceMap radianceMap;
  std::optional<FrameTargets> targets;

  void ensureTargets(int width, int height) {
    if (!targets || targets->width() != width || targets->height() != height) {
      targets.reset();  // free the old size first: two 4K target sets need not coexist
      targets.emplace(width, height);
    }
  }
};

// The EGL backend: one context and the GL objects of one frame size.
struct EglBackend {
  // Declared first so it is destroyed last, after every GL object.
  HeadlessGlContext context;
  std::unique_ptr<GpuObjects> gpu = std::make_unique<GpuObjects>();
  std::vector<float> sceneDepth;  // scratch, kept to avoid a per-frame allocation
  std::vector<float> rainRgba;    // scratch for the read-back layer of the streaks' radiance

  // GL objects are deleted by their owners' destructors, which needs this context current.
  ~EglBackend() {
    try {
      context.makeCurrent();
    } catch (const Error& error) {
      // The context is current on another thread. Deleting names now would hit whatever
      // context this thread has; the objects go with their own context in eglDestroyContext.
      log::warning(fmt::format("rain renderer destroyed off its thread: {}", error.what()));
      (void)gpu.release();
    }
  }

  void render(Image& frame, const OrderedStreaks& ordered, const rain::ShadingParams& shading,
              FarDropLines* farLines, const std::vector<rain::StreakInstance>& farStreaks);
};

}  // namespace

struct RainRenderer::Impl {
  std::unique_ptr<EglBackend> egl;  // one of the two
  std::unique_ptr<StreakRasterCpu> cpu;
  std::string description;
  FarDropLines farLines;
};

namespace {

// The far streaks' lines (far_drop_lines.h) under an interleaved premultiplied layer read back
// from the GPU: layer = layer + (1 - layer.A) * lines, as drawing the lines first would give.
void underlayFarLines(FarDropLines& lines, const std::vector<rain::StreakInstance>& farStreaks,
                      const rain::ShadingParams& shading, const Image& frame,
                      std::vector<float>& rgba) {
  const size_t n = frame.pixelCount();
  std::vector<float> planes(4 * n, 0.0f);
  const std::vector<float>* depth = frame.findPlane(kDepthPlane);
  lines.draw(farStreaks, shading,
             {planes.data(), planes.data() + n, planes.data() + 2 * n, planes.data() + 3 * n,
              depth ? depth->data() : nullptr, frame.width, frame.height});
  for (size_t i = 0; i < n; ++i) {
    float* pixel = rgba.data() + i * 4;
    const float keep = 1.0f - pixel[3];
    for (int c = 0; c < 4; ++c) pixel[c] += keep * planes[c * n + i];
  }
}

}  // namespace

void EglBackend::render(Image& frame, const OrderedStreaks& ordered,
                        const rain::ShadingParams& shading, FarDropLines* farLines,
                        const std::vector<rain::StreakInstance>& farStreaks) {
  context.makeCurrent();
  gpu->ensureTargets(frame.width, frame.height);
  // Without a depth plane every streak is in front (of kFarDepthMeters): the variant without
  // the depth fetch gives the same result.
  const bool hasDepth = frame.findPlane(kDepthPlane) != nullptr;
  if (hasDepth) comparableSceneDepth(frame, sceneDepth);
  gpu->targets->begin(hasDepth ? &sceneDepth : nullptr);
  gpu->streaks.upload(ordered.streaks);
  if (!shading.radianceMap.empty()) gpu->radianceMap.update(shading.radianceMap);
  gpu->program.use(shading, hasDepth, frame.width, frame.height, gpu->atlas.width(),
                   gpu->atlas.height());
  gpu->atlas.bind(kAtlasUnit, kStrokeRectBinding);
  gpu->radianceMap.bind(kRadianceMapUnit);
  if (hasDepth) gpu->targets->bindSceneDepth(kSceneDepthUnit);
  gpu->streaks.bind(kStreakBinding);
  for (const StreakBatch& batch : ordered.batches) {
    const bool lines =
        batch.lineWidthPx > 0.0f && batch.lineWidthPx <= gpu->streaks.maxLineWidthPx();
    gpu->program.setLines(lines);
    if (lines) {
      gpu->streaks.drawLines(batch.first, batch.count, batch.lineWidthPx);
    } else {
      gpu->streaks.drawTriangles(batch.first, batch.count);
    }
  }

  // The GPU drew alpha * C over transparent black; B and c enter on the CPU (rain_inputs.h).
  rainRgba.resize(frame.pixelCount() * 4);
  gpu->targets->readRainLayer(rainRgba.data());
  if (!farStreaks.empty()) underlayFarLines(*farLines, farStreaks, shading, frame, rainRgba);
  compositeRainLayer(rainRgba, shading.backgroundWeight, frame);
}

namespace {

std::atomic<RainBackend>& defaultBackend() {
  static std::atomic<RainBackend> backend{RainBackend::Auto};
  return backend;
}

}  // namespace

std::optional<RainBackend> rainBackendNamed(const std::string& given) {
  std::string name(given);
  std::transform(name.begin(), name.end(), name.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (name == "auto") return RainBackend::Auto;
  if (name == "egl") return RainBackend::Egl;
  if (name == "cpu") return RainBackend::Cpu;
  return std::nullopt;
}

void setRainBackend(RainBackend backend) {
  defaultBackend() = backend;
}

bool isSoftwareGlRenderer(const std::string& rendererDescription) {
  std::string lower(rendererDescription);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* software : {"llvmpipe", "softpipe", "swrast", "swiftshader"}) {
    if (lower.find(software) != std::string::npos) return true;
  }
  return false;
}

RainRenderer::RainRenderer(int width, int height, RainBackend backend)
    : impl_(std::make_unique<Impl>()) {
  if (width <= 0 || height <= 0) {
    throwRainError(fmt::format("cannot render rain into {}x{} pixels", width, height));
  }
  const bool fromDefault = backend == RainBackend::Auto;
  if (fromDefault) backend = defaultBackend();
  std::string why = fromDefault && backend != RainBackend::Auto ? "PLUVIA_RAIN_BACKEND" : "";
  if (backend == RainBackend::Auto && eglDevicesAreAllSoftware()) {
    why =
        "EGL's only devices are software ones (EGL_MESA_device_software); "
        "PLUVIA_RAIN_BACKEND=egl draws with them";
    backend = RainBackend::Cpu;
  }
  if (backend != RainBackend::Cpu) {
    try {
      impl_->egl = std::make_unique<EglBackend>();
      impl_->description = impl_->egl->context.deviceDescription();
    } catch (const Error& error) {
      if (backend == RainBackend::Egl) throw;
      why = fmt::format("EGL has no device: {}", error.what());
    }
    if (backend == RainBackend::Auto && impl_->egl && isSoftwareGlRenderer(impl_->description)) {
      why = fmt::format(
          "the EGL device is a software one: {}; PLUVIA_RAIN_BACKEND=egl draws with "
          "it",
          impl_->description);
      impl_->egl.reset();
    }
  }
  if (impl_->egl) {
    impl_->egl->gpu->ensureTargets(width, height);
    log::debug("rain renderer: EGL, " + impl_->description);
    return;
  }
  impl_->cpu = std::make_unique<StreakRasterCpu>();
  impl_->description =
      fmt::format("CPU streak rasteriser, {} threads{}", tbb::info::default_concurrency(),
                  why.empty() ? "" : " (" + why + ")");
  log::info("rain renderer: " + impl_->description);
}

RainRenderer::~RainRenderer() = default;

void RainRenderer::setStrokeAtlas(const rain::StrokeAtlas& atlas) {
  impl_->farLines.setStrokeMeans(atlas);
  if (impl_->cpu) {
    impl_->cpu->setStrokeAtlas(atlas);
    return;
  }
  impl_->egl->context.makeCurrent();
  impl_->egl->gpu->atlas.upload(atlas);
}

void RainRenderer::render(Image& frame, const std::vector<rain::StreakInstance>& streaks,
                          const rain::ShadingParams& shading,
                          const std::vector<rain::StreakInstance>& farStreaks) {
  validateFrame(frame);
  validateShading(shading);
  const int strokeCount =
      impl_->cpu ? impl_->cpu->strokeCount() : impl_->egl->gpu->atlas.strokeCount();
  validateStreaks(streaks, strokeCount);
  if (!farStreaks.empty()) validateStreaks(farStreaks, strokeCount);
  const OrderedStreaks ordered = orderForDrawing(streaks);
  if (ordered.streaks.empty() && farStreaks.empty()) {
    clearRainLayer(frame);
    return;
  }
  if (impl_->cpu) {
    impl_->cpu->render(frame, ordered.streaks, shading, &impl_->farLines, &farStreaks);
  } else if (ordered.streaks.empty()) {
    // Nothing for the GPU to draw: the lines alone, composited on the CPU.
    std::vector<float> layer(frame.pixelCount() * 4, 0.0f);
    underlayFarLines(impl_->farLines, farStreaks, shading, frame, layer);
    compositeRainLayer(layer, shading.backgroundWeight, frame);
  } else {
    impl_->egl->render(frame, ordered, shading, &impl_->farLines, farStreaks);
  }
}

std::string RainRenderer::deviceDescription() const {
  return impl_->description;
}

RainBackend RainRenderer::backend() const {
  return impl_->cpu ? RainBackend::Cpu : RainBackend::Egl;
}

}  // namespace pluvia::gpu
