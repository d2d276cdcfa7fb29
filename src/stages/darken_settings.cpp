#include "stages/darken_settings.h"

namespace pluvia {

const SettingsTable<DarkenSettings>& darkenTable() {
  static const SettingsTable<DarkenSettings> table(
      {.name = "darken",
       .help = "Desaturates toward luminance and darkens the plate (Starik–Werman).",
       .inputs = {"image"},
       .outputs = {"image"}},
      {
          bind(&DarkenSettings::enabled, enabledParam()),
          bind(&DarkenSettings::amount,
               fractionParam("amount", 0.0, "blend toward luminance; 0 leaves the plate as it is")),
          bind(&DarkenSettings::darkening,
               fractionParam("darkening", 0.5,
                             "brightness lost at amount 1: out *= 1 - amount*darkening")),
      });
  return table;
}

DarkenSettings darkenSettings(const Preset& p) {
  return darkenTable().read(p);
}

}  // namespace pluvia
