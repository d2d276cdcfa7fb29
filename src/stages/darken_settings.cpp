#include "stages/darken_settings.h"

namespace pluvia {

SectionSpec darkenSection() {
  SectionSpec s;
  s.name = "darken";
  s.help = "Desaturates toward luminance and darkens the plate (Starik–Werman).";
  s.inputs = {"image"};
  s.outputs = {"image"};
  s.params = {
      enabledParam(),
      numberParam("amount", 0.0, {0.0, 1.0}, "",
                  "blend toward luminance; 0 leaves the plate as it is"),
      numberParam("darkening", 0.5, {0.0, 1.0}, "",
                  "brightness lost at amount 1: out *= 1 - amount*darkening"),
  };
  return s;
}

DarkenSettings darkenSettings(const Preset& p) {
  DarkenSettings s;
  s.enabled = p.boolean("darken.enabled");
  s.amount = p.number("darken.amount");
  s.darkening = p.number("darken.darkening");
  return s;
}

}  // namespace pluvia
