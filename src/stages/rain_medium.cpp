#include "stages/rain_medium.h"

#include "rain/drop_physics.h"

namespace pluvia {

RainMedium mediumAt(const RainSettings& rain, const FogSettings& fog, double frame) {
  RainMedium medium;
  const double rate = rain.enabled ? rain.rateMmPerHour.valueAt(frame) : 0.0;
  medium.rainExtinctionPerMeter = rain::rainExtinctionPerMeter(rate);
  medium.rainVisibilityMeters = rain::rainVisibilityMeters(rate);
  medium.fogPerMeter = fog.enabled ? fog.densityPerMeter : 0.0;
  return medium;
}

}  // namespace pluvia
