#pragma once
// `pluvia bench --day`: the day-time stages (wet ground, splashes, ripples, skylight fog, rainbow)
// timed in the same render as the rain stage, and their cost as a fraction of the rain stage's.
#include <string>
#include <vector>

#include "util/timer.h"

namespace pluvia {

// --set overrides that put every day-time stage to work on the bench clip: fog.model =
// skylight (the preset's fog density; the model scatters through the rain even without fog), a
// sun behind the camera 30 deg up (rainbow), and a camera 1.6 m above the ground tilted 10 deg
// down, so that the ground within the splashes' level of detail is in view, and the ripples on
// (off by default). Given before the user's own --set, which win.
std::vector<std::string> dayBenchOverrides();

// The splash, fog and rainbow stages' milliseconds per frame, each over the rain stage's.
void printDayStageRatios(const StageTimes& times, int frames);

}  // namespace pluvia
