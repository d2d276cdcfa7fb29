#include "stages/derain_settings.h"

namespace pluvia {

SectionSpec derainSection() {
  SectionSpec s;
  s.name = "derain";
  s.help =
      "Cuts rain strokes out of real rain footage with Wang et al.'s Eq. (1) (used when "
      "rain.strokes is \"derain\").";
  s.outputs = {"footage_strokes"};
  s.params = {
      enabledParam("run this stage when its strokes are read"),
      stringParam("input", "", "rain footage to cut strokes from; empty: the render input"),
      integerParam("frames", 20, {3, 1000}, "frames",
                   "frames solved together (one derain window, from the footage's first frame)"),
      integerParam("count", 64, {1, 4096}, "strokes", "strokes kept, best first"),
  };
  return s;
}

DerainSettings derainSettings(const Preset& p) {
  DerainSettings s;
  s.enabled = p.boolean("derain.enabled");
  s.input = p.string("derain.input");
  s.frames = int(p.number("derain.frames"));
  s.strokeCount = int(p.number("derain.count"));
  s.resolved = p.at("derain");
  return s;
}

}  // namespace pluvia
