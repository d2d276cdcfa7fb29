#include "bench_day.h"

#include <algorithm>
#include <iostream>

#include <fmt/format.h>

namespace pluvia {

std::vector<std::string> dayBenchOverrides() {
  return {"fog.model=skylight",          "rainbow.sun=direction", "rainbow.sun_elevation_deg=30",
          "rainbow.sun_azimuth_deg=180", "camera.height_m=1.6",   "camera.tilt_deg=10",
          "ripples.enabled=true"};
}

void printDayStageRatios(const StageTimes& times, int frames) {
  const auto snapshot = times.snapshot();
  auto msPerFrame = [&](const std::string& stage) {
    const auto found = snapshot.find(stage);
    return found == snapshot.end() ? 0.0 : 1000.0 * found->second.first / std::max(1, frames);
  };
  const double rain = msPerFrame("rain");
  std::cout << fmt::format("\nday stages against the rain stage (same render, {} frames)\n",
                           frames);
  std::cout << fmt::format("{:<10} {:>10} {:>14}\n", "stage", "ms/frame", "/ rain stage");
  std::cout << fmt::format("{:<10} {:>10.2f} {:>14}\n", "rain", rain, "1");
  for (const char* stage : {"wet_ground", "splash", "ripples", "fog", "rainbow"}) {
    const double ms = msPerFrame(stage);
    std::cout << fmt::format("{:<10} {:>10.2f} {:>14.3f}\n", stage, ms,
                             rain > 0.0 ? ms / rain : 0.0);
  }
}

}  // namespace pluvia
