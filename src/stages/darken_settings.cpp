#include "stages/darken_settings.h"

#include "stages/clip_plate_rain.h"

namespace pluvia {

const SettingsTable<DarkenSettings>& darkenTable() {
  static const SettingsTable<DarkenSettings> table(
      {.name = "darken",
       .help = "Desaturates toward luminance and darkens the plate (Starik–Werman), more with "
               "depth; --aov darken writes what it changed.",
       .inputs = {"image", "depth", "plate_rain"},
       .outputs = {"image"}},
      {
          bind(&DarkenSettings::enabled, enabledParam()),
          bind(&DarkenSettings::overRain, overRainParam()),
          bind(&DarkenSettings::amount,
               fractionParam("amount", 0.0, "blend toward luminance; 0 leaves the plate as it is")),
          bind(&DarkenSettings::darkening,
               fractionParam("darkening", 0.5,
                             "brightness lost at amount 1: out *= 1 - amount*darkening")),
          bind(&DarkenSettings::distanceMeters,
               numberParam("distance_m", 30.0, {0.0, 1e6}, "m",
                           "the rain between camera and scene darkens by depth z: amount * (1 - "
                           "exp(-z / distance_m)), the sky the whole amount; 0: every pixel "
                           "alike")),
      });
  return table;
}

DarkenSettings darkenSettings(const Preset& p) {
  return darkenTable().read(p);
}

}  // namespace pluvia
