// `pluvia bench --drops N`: CPU time of the drop simulation per frame (one step and the
// streaks it projects), still air against the full model (gusts, a stable-fluids wind field,
// rain cells), measured in the same run; and the step again after frame 1000, which must cost
// the same (nothing grows with the clip's length).
#include "bench_drops.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <vector>

#include <fmt/format.h>

#include "bench_timing.h"
#include "rain/drop_simulation.h"
#include "util/timer.h"

namespace pluvia {
namespace {

struct DropTimes {
  double stepMs = 0.0, streaksMs = 0.0;
  double lateStepMs = 0.0;  // the same steps after frame 1000: cost must not grow with the clip
  size_t streaks = 0;
};

// Median step and streak times of `frames` frames from `firstFrame` on.
void timeFrames(rain::DropSimulation& sim, int64_t firstFrame, int frames, double& stepMs,
                double& streaksMs, size_t& streakCount) {
  std::vector<double> step, streaks;
  for (int64_t f = firstFrame; f < firstFrame + frames; ++f) {
    auto started = std::chrono::steady_clock::now();
    sim.advanceTo(f);
    step.push_back(secondsSince(started) * 1e3);
    started = std::chrono::steady_clock::now();
    streakCount = sim.buildStreaks(rain::StreakSettings{}).size();
    streaks.push_back(secondsSince(started) * 1e3);
  }
  stepMs = median(step);
  streaksMs = median(streaks);
}

constexpr int64_t kLateFrame = 1000;

DropTimes timeSimulation(int64_t drops, int frames, bool fullModel) {
  rain::DropSimulationSettings s;
  s.maxDrops = drops;
  s.farMeters = 15.0;
  s.lastFrame = kLateFrame + frames;
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
  DropTimes t;
  timeFrames(sim, 4, frames, t.stepMs, t.streaksMs, t.streaks);
  sim.advanceTo(kLateFrame - 1);
  double lateStreaksMs = 0.0;
  size_t lateStreaks = 0;
  timeFrames(sim, kLateFrame, frames, t.lateStepMs, lateStreaksMs, lateStreaks);
  return t;
}

}  // namespace

void runDropBench(int64_t drops, int frames) {
  std::cout << fmt::format(
      "bench drops: {} drops at 1920x1080, median of {} frames (CPU, all threads)\n", drops,
      frames);
  std::cout << fmt::format("{:<44} {:>10} {:>12} {:>9} {:>16}\n", "model", "step ms", "streaks ms",
                           "streaks", "step ms @1000");
  const DropTimes still = timeSimulation(drops, frames, false);
  const DropTimes full = timeSimulation(drops, frames, true);
  std::cout << fmt::format("{:<44} {:>10.2f} {:>12.2f} {:>9} {:>16.2f}\n", "still air (baseline)",
                           still.stepMs, still.streaksMs, still.streaks, still.lateStepMs);
  std::cout << fmt::format("{:<44} {:>10.2f} {:>12.2f} {:>9} {:>16.2f}\n",
                           "gusts + stable-fluids wind + 3 rain cells", full.stepMs, full.streaksMs,
                           full.streaks, full.lateStepMs);
  std::cout << fmt::format("full model / baseline: step x{:.2f}, step + streaks x{:.2f}\n",
                           full.stepMs / still.stepMs,
                           (full.stepMs + full.streaksMs) / (still.stepMs + still.streaksMs));
}

}  // namespace pluvia
