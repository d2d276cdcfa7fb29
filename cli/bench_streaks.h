#pragma once
// The streak populations of `pluvia bench --strokes`: deterministic, so every run and every
// build draws the same streaks.
#include <string>
#include <vector>

#include "rain/streak_types.h"

namespace pluvia {

struct StreakPopulation {
  std::string description;
  std::vector<rain::StreakInstance> streaks;
  double pixelsCovered = 0.0;  // sum of the quads' areas
};

// Long streaks everywhere (a stress test, not rain a camera records): 92 % "far", width
// 1.5-3 px and length 10-60 px; 8 % "near", width 3-7 px and length 60-200 px; alpha
// 0.05-0.3; a common slant of 8 +- 3 degrees; heads uniform over the frame.
StreakPopulation syntheticStreaks(int count, int width, int height, int strokeCount);

// What the drop simulation gives for heavy rain (Mizukami's 40 mm/h) seen by a 60-degree
// camera 1.6 m above the ground with a 1/60 s exposure and a 3 m/s breeze: drop sizes, depths
// 0.5-15 m, streak lengths and widths from the physics, the density scaled until `count`
// streaks are visible (the first `count` are kept).
StreakPopulation simulatedStreaks(int count, int width, int height, const rain::StrokeAtlas& atlas);

}  // namespace pluvia
