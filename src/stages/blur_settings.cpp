#include "stages/blur_settings.h"

#include "stages/clip_plate_rain.h"

namespace pluvia {

const SettingsTable<BlurSettings>& blurTable() {
  static const SettingsTable<BlurSettings> table(
      {.name = "blur",
       .help = "Gaussian blur of the plate (light scattered by the drops on its way), more with "
               "depth; --aov blur writes what it changed.",
       .inputs = {"image", "depth", "plate_rain"},
       .outputs = {"image"}},
      {
          bind(&BlurSettings::enabled, enabledParam()),
          bind(&BlurSettings::overRain, overRainParam()),
          bind(&BlurSettings::sigmaPx, numberParam("sigma_px", 0.0, {0.0, 100.0}, "px",
                                                   "standard deviation; 0 leaves the plate sharp")),
          bind(&BlurSettings::distanceMeters,
               numberParam("distance_m", 30.0, {0.0, 1e6}, "m",
                           "the blurred plate is mixed in by depth z: 1 - exp(-z / distance_m), "
                           "the sky wholly; 0: every pixel alike")),
      });
  return table;
}

BlurSettings blurSettings(const Preset& p) {
  return blurTable().read(p);
}

}  // namespace pluvia
