// `pluvia bench --drops N`: CPU time of the drop simulation per frame (one step and the
// streaks it projects), still air against the full model (gusts, a stable-fluids wind field,
// rain cells), measured in the same run.
#include "bench_drops.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <vector>

#include <fmt/format.h>

#include "rain/drop_simulation.h"
#include "util/timer.h"

namespace pluvia {
namespace {

struct DropTimes {
  double stepMs = 0.0, streaksMs = 0.0;
  size_t streaks = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

DropTimes timeSimulation(int64_t drops, int frames, bool fullModel) {
  rain::DropSimulationSettings s;
  s.maxDrops = drops;
  s.farMeters = 15.0;
  s.lastFrame = frames + 3;
  if (fullModel) {
    s.wind.gustiness = 0.5;
    s.wind.turbulence = 0.5;
    s.cells.count = 3;
    s.spreadMetersPerSecond = 0.5;
  }
  const Camera camera = Camera::fromFieldOfView(1920, 1080, 50, 5, 1.6);
  rain::DropSimulation sim(
      s, [camera](double) { return camera; },
      [fullModel](double) {
        rain::RainAtFrame r;
        r.rateMmPerHour = 500.0;  // the pool is filled to the cap
        r.windSpeedMetersPerSecond = fullModel ? 8.0 : 0.0;
        return r;
      });
  sim.advanceTo(3);  // warm-up
  std::vector<double> step, streaks;
  DropTimes t;
  for (int f = 4; f < 4 + frames; ++f) {
    auto started = std::chrono::steady_clock::now();
    sim.advanceTo(f);
    step.push_back(secondsSince(started) * 1e3);
    started = std::chrono::steady_clock::now();
    t.streaks = sim.buildStreaks(rain::StreakSettings{}).size();
    streaks.push_back(secondsSince(started) * 1e3);
  }
  t.stepMs = median(step);
  t.streaksMs = median(streaks);
  return t;
}

}  // namespace

void runDropBench(int64_t drops, int frames) {
  std::cout << fmt::format(
      "bench drops: {} drops at 1920x1080, median of {} frames (CPU, all threads)\n", drops,
      frames);
  std::cout << fmt::format("{:<44} {:>10} {:>12} {:>9}\n", "model", "step ms", "streaks ms",
                           "streaks");
  const DropTimes still = timeSimulation(drops, frames, false);
  const DropTimes full = timeSimulation(drops, frames, true);
  std::cout << fmt::format("{:<44} {:>10.2f} {:>12.2f} {:>9}\n", "still air (baseline)",
                           still.stepMs, still.streaksMs, still.streaks);
  std::cout << fmt::format("{:<44} {:>10.2f} {:>12.2f} {:>9}\n",
                           "gusts + stable-fluids wind + 3 rain cells", full.stepMs, full.streaksMs,
                           full.streaks);
  std::cout << fmt::format("full model / baseline: step x{:.2f}, step + streaks x{:.2f}\n",
                           full.stepMs / still.stepMs,
                           (full.stepMs + full.streaksMs) / (still.stepMs + still.streaksMs));
}

}  // namespace pluvia
