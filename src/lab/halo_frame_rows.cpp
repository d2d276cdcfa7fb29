#include "lab/halo_frame_rows.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "geometry/camera.h"
#include "image/image.h"
#include "optics/light_halos.h"
#include "util/timer.h"

namespace pluvia::lab {
namespace {

// A street at night: sky above the horizon, the ground 1.6 m below the camera, a wall 12 m away
// over the right third (depth edges against both).
Image streetFrame(const Camera& camera) {
  Image image(camera.width, camera.height);
  std::fill(image.rgba.begin(), image.rgba.end(), 0.0f);
  std::vector<float>& depth = image.plane(kDepthPlane);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const double below = (y + 0.5 - camera.cy) / camera.focalPx;
      double z = below > 0.0 ? 1.6 / below : HUGE_VAL;
      if (x > camera.width * 2 / 3 && y > camera.height / 5) z = std::min(z, 12.0);
      depth[static_cast<size_t>(y) * camera.width + x] = float(z);
    }
  return image;
}

// Street lamps 5 to 40 m ahead, every fifth a spot pointing down (as the bench presets).
std::vector<optics::LocalLight> streetLights(int count) {
  std::mt19937 random(18);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<optics::LocalLight> lights;
  for (int i = 0; i < count; ++i) {
    optics::LocalLight light;
    light.positionMeters = {-8 + 16 * unit(random), 0.5 + 4.5 * unit(random),
                            -5 - 35 * unit(random)};
    light.rgbIntensity = {50.0, 40.0, 27.5};
    if (i % 5 == 4) {
      light.spot = true;
      light.axis = {0, -1, 0};
      light.cosHalfAngle = std::cos(25.0 * M_PI / 180.0);
      light.falloffQ = 0.3;
      light.rgbIntensity = {120.0, 135.0, 150.0};
    }
    lights.push_back(light);
  }
  return lights;
}

}  // namespace

void addHaloFrameRows(LightsReport& report, bool quick) {
  const int width = quick ? 480 : 960, height = quick ? 270 : 540;
  const Camera camera = Camera::fromFieldOfView(width, height, 50.0, 0.0, 1.6);
  const optics::ScatteringTables tables;
  constexpr double kBeta = 0.003, kThreshold = 1e-3;  // moderate rain and fog; the default
  for (int count : quick ? std::vector<int>{10} : std::vector<int>{10, 100}) {
    const std::vector<optics::LocalLight> lights = streetLights(count);
    Image tiled = streetFrame(camera), every = tiled;
    auto started = std::chrono::steady_clock::now();
    optics::addHalos(tiled, camera, lights, kBeta, tables, kThreshold);
    const double tiledSeconds = secondsSince(started);
    started = std::chrono::steady_clock::now();
    optics::addHalos(every, camera, lights, kBeta, tables, kThreshold, true);
    const double everySeconds = secondsSince(started);
    // Relative to each pixel's own value, where it is at least a tenth of the threshold.
    double sum = 0.0, worst = 0.0;
    int n = 0;
    for (size_t i = 0; i < every.pixelCount(); ++i)
      for (int c = 0; c < 3; ++c) {
        const double reference = every.rgba[i * 4 + size_t(c)];
        if (!(reference >= 0.1 * kThreshold)) continue;
        const double e = std::abs(tiled.rgba[i * 4 + size_t(c)] - reference) / reference;
        sum += e;
        worst = std::max(worst, e);
        ++n;
      }
    const double pixels = double(width) * height;
    report.rows.push_back({"halo frame", fmt::format("tiles, {} lights", count),
                           sum / std::max(n, 1), worst, 1e9 * tiledSeconds / pixels});
    report.rows.push_back({"reference", fmt::format("halo frame: every pixel, {} lights", count),
                           0.0, 0.0, 1e9 * everySeconds / pixels});
    report.notes.push_back(fmt::format(
        "halo frame, {} lights at {}x{}: the lights stage's 16 px tiles against every pixel "
        "evaluated (no culling); error relative to each pixel's own value where it is at least a "
        "tenth of lights.halo_threshold; "
        "{:.0f} ms against {:.0f} ms a frame; ns/eval per pixel",
        count, width, height, 1e3 * tiledSeconds, 1e3 * everySeconds));
  }
}

}  // namespace pluvia::lab
