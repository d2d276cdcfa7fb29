// `pluvia bench --strokes` and `pluvia-bench-strokes`: frames per second of
// RainRenderer::render alone for deterministic streak populations (Table 3 of Wang et al.).
#include "bench_strokes.h"

#include <chrono>
#include <cmath>
#include <iostream>

#include <fmt/format.h>

#include "bench_streaks.h"
#include "bench_timing.h"
#include "gpu/rain_renderer.h"
#include "lab/test_environment.h"
#include "option_values.h"
#include "util/timer.h"

namespace pluvia {
namespace {

struct RenderTiming {
  double wallMs = 0.0;  // median
  double cpuMs = 0.0;   // median, all threads
};

// Median milliseconds of `frames` renders after 3 warm-up renders. Each render starts from the
// same background (copied outside the timed region) and includes everything render() does:
// streak upload, draw, read-back and the CPU-side planes. The process CPU time is reported too:
// on a shared machine it varies less than the wall time.
RenderTiming timeRenders(gpu::RainRenderer& renderer, const Image& background,
                         const std::vector<rain::StreakInstance>& streaks,
                         const rain::ShadingParams& shading, int frames) {
  std::vector<double> wall, cpu;
  Image frame;
  for (int i = 0; i < 3 + frames; ++i) {
    frame = background;
    const auto started = std::chrono::steady_clock::now();
    const double cpuStarted = processCpuMs();
    renderer.render(frame, streaks, shading);
    const double elapsed = 1000.0 * secondsSince(started);
    if (i >= 3) {
      wall.push_back(elapsed);
      cpu.push_back(processCpuMs() - cpuStarted);
    }
  }
  return {median(wall), median(cpu)};
}

Image benchBackground(int width, int height, bool depthPlane) {
  Image background(width, height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      float* p = background.pixel(x, y);
      p[0] = 0.2f + 0.6f * static_cast<float>(x) / static_cast<float>(width);
      p[1] = 0.3f + 0.4f * static_cast<float>(y) / static_cast<float>(height);
      p[2] = 0.5f;
    }
  }
  if (depthPlane) {
    std::vector<float>& depth = background.plane(kDepthPlane);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        depth[static_cast<size_t>(y) * width + x] = 3.0f + 47.0f * static_cast<float>(y) / height;
      }
    }
  }
  return background;
}

gpu::RainBackend parseBackend(const std::string& name) {
  if (name == "egl") return gpu::RainBackend::Egl;
  if (name == "cpu") return gpu::RainBackend::Cpu;
  return gpu::RainBackend::Auto;
}

// Each backend asked for ("both": EGL, then the CPU rasteriser) times every count on both
// populations in this one run; with two backends a last table gives the CPU's frames per second
// over EGL's.
}  // namespace

void runStrokeBench(const rain::StrokeAtlas& atlas, const std::string& strokeList,
                    const std::string& size, int frames, bool depthPlane,
                    const std::string& backends) {
  const std::vector<int> counts =
      cli::parseNumberList(strokeList, "--strokes", 1, 10000000, "counts", "count");
  const auto [width, height] = cli::parseFrameSize(size, 1, "720x480");
  const int strokeCount = static_cast<int>(atlas.rects.size());
  rain::ShadingParams shading;  // pluvia's default: the map term alone, c = 0
  shading.radianceMap = lab::builtinTestEnvironment(128);
  const Image background = benchBackground(width, height, depthPlane);

  std::cout << fmt::format("bench strokes: {}x{}, {} frames each (median, after 3 warm-up)\n",
                           width, height, frames);
  std::cout << fmt::format("atlas: {} strokes ({}x{}); radiance map {}x{}; scene depth: {}\n",
                           strokeCount, atlas.width, atlas.height, shading.radianceMap.width,
                           shading.radianceMap.height, depthPlane ? "plane 3-50 m" : "none (far)");
  std::cout << "timing: RainRenderer::render end to end (streak upload, draw, read-back, planes)\n";

  std::vector<StreakPopulation> populations[2];
  for (int count : counts) {
    populations[0].push_back(syntheticStreaks(count, width, height, strokeCount));
    populations[1].push_back(simulatedStreaks(count, width, height, atlas));
  }
  const std::vector<std::string> names =
      backends == "both" ? std::vector<std::string>{"egl", "cpu"} : std::vector{backends};
  std::vector<std::vector<double>> fps(names.size());  // [backend][population * counts + i]
  for (size_t b = 0; b < names.size(); ++b) {
    gpu::RainRenderer renderer(width, height, parseBackend(names[b]));
    renderer.setStrokeAtlas(atlas);
    std::cout << fmt::format("\nbackend {}: {}\n", names[b], renderer.deviceDescription());
    const RenderTiming overhead =
        timeRenders(renderer, background, syntheticStreaks(1, width, height, strokeCount).streaks,
                    shading, frames);
    std::cout << fmt::format(
        "fixed cost per frame (1 streak: uploads, read-back, planes): {:.2f} ms ({:.2f} ms CPU)\n",
        overhead.wallMs, overhead.cpuMs);
    for (int simulated = 0; simulated < 2; ++simulated) {
      std::cout << fmt::format("{:>9} {:>10} {:>9} {:>12} {:>9} {:>12}  {}\n", "strokes",
                               "ms/frame", "fps", "Mpx covered", "Mpx/s", "CPU ms/frame",
                               simulated ? "simulated rain" : "synthetic stress test");
      for (const StreakPopulation& population : populations[simulated]) {
        const RenderTiming t =
            timeRenders(renderer, background, population.streaks, shading, frames);
        const double megapixels = population.pixelsCovered / 1e6;
        fps[b].push_back(1000.0 / t.wallMs);
        std::cout << fmt::format("{:>9} {:>10.2f} {:>9.1f} {:>12.2f} {:>9.1f} {:>12.2f}\n",
                                 population.streaks.size(), t.wallMs, 1000.0 / t.wallMs, megapixels,
                                 megapixels / (t.wallMs / 1000.0), t.cpuMs);
        std::cout.flush();
      }
      std::cout << "  (" << populations[simulated].front().description << ")\n";
    }
  }
  if (names.size() == 2) {
    std::cout << fmt::format("\n{:>9} {:>16} {:>16}  (frames/s, {} over {}, same run)\n", "strokes",
                             "synthetic", "simulated", names[1], names[0]);
    for (size_t i = 0; i < counts.size(); ++i) {
      std::cout << fmt::format("{:>9} {:>16.2f} {:>16.2f}\n", counts[i], fps[1][i] / fps[0][i],
                               fps[1][counts.size() + i] / fps[0][counts.size() + i]);
    }
  }
  std::cout << "(CPU ms/frame: all threads of the process, llvmpipe's included; on a shared "
               "machine it varies less than the wall time)\n";
}

}  // namespace pluvia
