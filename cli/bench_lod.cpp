// `pluvia bench --lod 0,0.5,1,1.5`: error against time of the far drops drawn as lines
// (rain.lod_px, gpu/far_drop_lines.h). One simulated frame of `moderate` rain (8 mm/h or
// --rate, 2.5 m/s wind, drops 0.5-15 m, 1/48 s exposure, a 60-degree camera 1.6 m up, level) over a
// street-like scene depth (sky in the top third, the ground below), rendered by the renderer a
// render would choose, once per lod_px. Each is compared with drawing every drop (lod_px 0) on the
// rain AOV (the premultiplied layer rain.R, rain.G, rain.B): the mean and max absolute difference,
// and the layer's mean radiance and mean coverage (rain.A) over those of drawing every drop.
#include "bench_lod.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <vector>

#include <fmt/format.h>

#include "bench_timing.h"
#include "common.h"
#include "geometry/camera.h"
#include "gpu/rain_renderer.h"
#include "lab/test_environment.h"
#include "rain/drop_simulation.h"
#include "rain/stroke_library.h"
#include "util/error.h"
#include "util/timer.h"

namespace pluvia {
namespace {

// Sky (infinitely far) over the top third, a level ground below seen from 1.6 m.
Image streetDepth(int width, int height) {
  Image frame(width, height);
  for (size_t i = 0; i < frame.pixelCount(); ++i) {
    frame.rgba[i * 4 + 0] = 0.3f, frame.rgba[i * 4 + 1] = 0.3f, frame.rgba[i * 4 + 2] = 0.3f;
  }
  std::vector<float>& depth = frame.plane(kDepthPlane);
  for (int y = 0; y < height; ++y) {
    const float d = y < height / 3
                        ? INFINITY
                        : 20.0f * static_cast<float>(height) /
                              (3.0f * static_cast<float>(y) - static_cast<float>(height) + 3.0f);
    std::fill_n(depth.begin() + static_cast<ptrdiff_t>(y) * width, width, d);
  }
  return frame;
}

struct Layer {
  std::vector<float> r, g, b, a;
};

Layer layerOf(const Image& frame) {
  return {*frame.findPlane("rain.R"), *frame.findPlane("rain.G"), *frame.findPlane("rain.B"),
          *frame.findPlane("rain.A")};
}

double mean(const std::vector<float>& v) {
  double sum = 0.0;
  for (float x : v) sum += x;
  return sum / static_cast<double>(v.size());
}

}  // namespace

void runLodBench(const std::string& lodList, const std::string& size, int frames,
                 double rateMmPerHour) {
  const std::vector<double> lods =
      cli::parseNumberList(lodList, "--lod", 0.0, 10.0, "pixel sizes", "size");
  const auto [width, height] = cli::parseFrameSize(size, 16, "1920x1080");
  const rain::StrokeLibrary library = rain::loadStrokeLibrary(rain::builtinStrokeLibraryPath());
  rain::ShadingParams shading;  // pluvia's default: the map term alone, c = 0
  shading.radianceMap = lab::builtinTestEnvironment(128);

  rain::DropSimulationSettings settings;  // rain's defaults: 0.8 mm and up, 15 m, 100000 drops
  settings.nearMeters = 0.5;
  settings.seed = 20;
  settings.stepSeconds = 1.0 / 24.0;
  const Camera camera = Camera::fromFieldOfView(width, height, 60.0, 0.0, 1.6);
  rain::RainAtFrame moderate;
  moderate.rateMmPerHour = rateMmPerHour;
  moderate.windSpeedMetersPerSecond = 2.5;
  moderate.windDirectionDeg = 20.0;
  rain::DropSimulation simulation(
      settings, [camera](double) { return camera; }, [moderate](double) { return moderate; });
  simulation.advanceTo(2);
  rain::StreakSettings look;
  look.exposureSeconds = 1.0 / 48.0;
  look.strokeCount = static_cast<int>(library.atlas.rects.size());
  look.meanMatte = rain::meanMatte(library.atlas);

  gpu::RainRenderer renderer(width, height);
  renderer.setStrokeAtlas(library.atlas);
  const Image background = streetDepth(width, height);
  std::cout << fmt::format(
      "bench lod: {}x{}, {} mm/h (moderate's 8 unless --rate), 2.5 m/s, {} renders each (median "
      "after 2 warm-up), {}\n",
      width, height, rateMmPerHour, frames, renderer.deviceDescription());
  std::cout << fmt::format(
      "{:>7} {:>8} {:>8} {:>9} {:>8} {:>7} {:>8} {:>11} {:>10} {:>10} {:>10}\n", "lod_px",
      "streaks", "lines", "ms/frame", "speed", "CPU ms", "CPU spd", "mean|diff|", "max|diff|",
      "radiance", "coverage");
  Layer reference;
  double referenceMs = 0.0, referenceCpuMs = 0.0;
  for (size_t k = 0; k < lods.size(); ++k) {
    look.lodPx = lods[k];
    std::vector<rain::StreakInstance> far;
    const std::vector<rain::StreakInstance> near = simulation.buildStreaks(look, &far);
    Image frame;
    std::vector<double> ms, cpuMs;
    for (int i = 0; i < frames + 2; ++i) {
      frame = background;
      const auto started = std::chrono::steady_clock::now();
      const double cpuStarted = processCpuMs();
      renderer.render(frame, near, shading, far);
      if (i >= 2) {
        ms.push_back(1000.0 * secondsSince(started));
        cpuMs.push_back(processCpuMs() - cpuStarted);
      }
    }
    const double wallMedian = median(ms), cpuMedian = median(cpuMs);
    const Layer layer = layerOf(frame);
    if (k == 0) {
      if (lods[0] != 0.0) throw UsageError("--lod must start with 0 (every drop, the reference)");
      reference = layer;
      referenceMs = wallMedian;
      referenceCpuMs = cpuMedian;
    }
    double sumDiff = 0.0, maxDiff = 0.0;
    const std::vector<float>* planes[3] = {&layer.r, &layer.g, &layer.b};
    const std::vector<float>* referencePlanes[3] = {&reference.r, &reference.g, &reference.b};
    for (int c = 0; c < 3; ++c) {
      for (size_t i = 0; i < layer.r.size(); ++i) {
        const double d = std::abs(double((*planes[c])[i]) - double((*referencePlanes[c])[i]));
        sumDiff += d, maxDiff = std::max(maxDiff, d);
      }
    }
    const double radiance = mean(layer.r) + mean(layer.g) + mean(layer.b);
    const double referenceRadiance = mean(reference.r) + mean(reference.g) + mean(reference.b);
    std::cout << fmt::format(
        "{:>7.2f} {:>8} {:>8} {:>9.2f} {:>7.2f}x {:>7.1f} {:>7.2f}x {:>11.2e} {:>10.4f} {:>10.4f} "
        "{:>10.4f}\n",
        lods[k], near.size(), far.size(), wallMedian, referenceMs / wallMedian, cpuMedian,
        referenceCpuMs / cpuMedian, sumDiff / (3.0 * static_cast<double>(layer.r.size())), maxDiff,
        radiance / referenceRadiance, mean(layer.a) / mean(reference.a));
    std::cout.flush();
  }
  std::cout << "(diff: the rain AOV rain.R/G/B against lod_px 0, linear; radiance and coverage: "
               "the layer's mean RGB and mean rain.A over lod_px 0's)\n";
}

}  // namespace pluvia
