#include "stages/blur_settings.h"

namespace pluvia {

const SettingsTable<BlurSettings>& blurTable() {
  static const SettingsTable<BlurSettings> table(
      {.name = "blur",
       .help = "Gaussian blur of the plate (refraction through rain).",
       .inputs = {"image"},
       .outputs = {"image"}},
      {
          bind(&BlurSettings::enabled, enabledParam()),
          bind(&BlurSettings::sigmaPx, numberParam("sigma_px", 0.0, {0.0, 100.0}, "px",
                                                   "standard deviation; 0 leaves the plate sharp")),
      });
  return table;
}

BlurSettings blurSettings(const Preset& p) {
  return blurTable().read(p);
}

}  // namespace pluvia
