#pragma once
// The medium the rain and the fog make at a frame, as every stage that sends light through it
// (fog, lights, rainbow) takes it: what light loses per metre to each, and how far one sees
// through the rain.
#include "stages/fog_settings.h"
#include "stages/rain_settings.h"

namespace pluvia {

struct RainMedium {
  double rainExtinctionPerMeter = 0.0;  // at the frame's rate; 0 with the rain off
  double fogPerMeter = 0.0;             // fog.density; 0 with the fog off
  double rainVisibilityMeters = 0.0;    // through the rain (rain/drop_physics.h); inf without it
  double extinctionPerMeter() const { return rainExtinctionPerMeter + fogPerMeter; }
};

RainMedium mediumAt(const RainSettings& rain, const FogSettings& fog, double frame);

}  // namespace pluvia
