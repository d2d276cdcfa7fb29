#include "stages/derain_settings.h"

namespace pluvia {

const SettingsTable<DerainSettings>& derainTable() {
  using S = DerainSettings;
  static const SettingsTable<DerainSettings> table(
      {.name = "derain",
       .help = "Cuts rain strokes out of real rain footage with Wang et al.'s Eq. (1) (used when "
               "rain.strokes is \"derain\").",
       .outputs = {"footage_strokes"}},
      {
          bind(&S::enabled, enabledParam("run this stage when its strokes are read")),
          bind(&S::input,
               pathParam("input", "", "rain footage to cut strokes from; empty: the render input")),
          bind(&S::frames, integerParam("frames", 20, {3, 1000}, "frames",
                                        "frames solved together (one derain window, from the "
                                        "footage's first frame)")),
          bind(&S::strokeCount,
               integerParam("count", 64, {1, 4096}, "strokes", "strokes kept, best first")),
      });
  return table;
}

DerainSettings derainSettings(const Preset& p) {
  return derainTable().read(p);
}

}  // namespace pluvia
