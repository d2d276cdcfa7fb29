#include "bench_streaks.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>

#include "geometry/camera.h"
#include "rain/drop_simulation.h"
#include "rain/stroke_library.h"

namespace pluvia {
namespace {

double quadArea(const rain::StreakInstance& s) {
  const double length = std::hypot(s.tailX - s.headX, s.tailY - s.headY);
  return (length + s.widthPx) * s.widthPx;
}

}  // namespace

StreakPopulation syntheticStreaks(int count, int width, int height, int strokeCount) {
  std::mt19937 random(20060101u + static_cast<unsigned>(count));
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float focalPx =
      0.5f * static_cast<float>(width) / std::tan(0.5f * 60.0f * 3.14159265f / 180.0f);
  StreakPopulation population;
  population.description =
      "synthetic stress test: 92% width 1.5-3 px, length 10-60 px; 8% width 3-7 px, length "
      "60-200 px; alpha 0.05-0.3; slant 8+-3 deg";
  population.streaks.reserve(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    const bool near = unit(random) < 0.08f;
    const float widthPx = near ? 3.0f + 4.0f * unit(random) : 1.5f + 1.5f * unit(random);
    const float lengthPx = near ? 60.0f + 140.0f * unit(random) : 10.0f + 50.0f * unit(random);
    const float depth = near ? 0.5f + 3.5f * unit(random) : 4.0f + 36.0f * unit(random);
    const float slant = (8.0f + 6.0f * (unit(random) - 0.5f)) * 3.14159265f / 180.0f;
    const float headX = static_cast<float>(width) * unit(random);
    const float headY = static_cast<float>(height) * unit(random) - 0.5f * lengthPx;
    const float alpha = 0.05f + 0.25f * unit(random);
    const float stroke = std::min(static_cast<float>(strokeCount - 1),
                                  std::floor(unit(random) * static_cast<float>(strokeCount)));
    // Camera looks down -z, y up; image y grows downward.
    float vx = headX - 0.5f * static_cast<float>(width);
    float vy = 0.5f * static_cast<float>(height) - headY;
    float vz = -focalPx;
    const float n = std::sqrt(vx * vx + vy * vy + vz * vz);
    population.streaks.push_back({headX, headY, headX + lengthPx * std::sin(slant),
                                  headY + lengthPx * std::cos(slant), widthPx, alpha, depth, stroke,
                                  vx / n, vy / n, vz / n, 0.0f});
    population.pixelsCovered += quadArea(population.streaks.back());
  }
  return population;
}

StreakPopulation simulatedStreaks(int count, int width, int height,
                                  const rain::StrokeAtlas& atlas) {
  rain::DropSimulationSettings settings;
  settings.maxDrops = std::max<int64_t>(100000, int64_t(count) * 8);
  settings.seed = 20060101u;
  const Camera camera = Camera::fromFieldOfView(width, height, 60.0, 0.0, 1.6);
  rain::StreakSettings look;
  look.exposureSeconds = 1.0 / 60.0;
  look.strokeCount = static_cast<int>(atlas.rects.size());
  look.meanMatte = rain::meanMatte(atlas);

  // Visible streaks grow in proportion to the density scale (the pool holds up to maxDrops):
  // measure at scale 1, then scale to the count asked for, with a 10 % surplus.
  auto streaksAt = [&](double densityScale) {
    rain::RainAtFrame rain;
    rain.rateMmPerHour = 40.0;
    rain.densityScale = densityScale;
    rain.windSpeedMetersPerSecond = 3.0;
    rain::DropSimulation simulation(
        settings, [camera](double) { return camera; }, [rain](double) { return rain; });
    simulation.advanceTo(2);
    return simulation.buildStreaks(look);
  };
  const size_t atUnitScale = std::max<size_t>(1, streaksAt(1.0).size());
  StreakPopulation population;
  population.streaks = streaksAt(1.1 * double(count) / double(atUnitScale));
  if (population.streaks.size() > size_t(count)) population.streaks.resize(size_t(count));
  for (const auto& s : population.streaks) population.pixelsCovered += quadArea(s);
  population.description = fmt::format(
      "simulated heavy rain (40 mm/h, 1/60 s, 60 deg camera, drops 0.5-15 m), {} streaks at "
      "unit density",
      atUnitScale);
  return population;
}

}  // namespace pluvia
