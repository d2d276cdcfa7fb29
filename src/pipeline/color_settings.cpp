#include "pipeline/color_settings.h"

namespace pluvia {

const SettingsTable<ColorSettings>& colorTable() {
  using S = ColorSettings;
  static const SettingsTable<ColorSettings> table(
      {.name = "color",
       .help =
           "OpenColorIO colour spaces at the two ends; everything between is scene-linear float."},
      {
          bind(&S::inputSpace,
               stringParam("input", "auto",
                           "input colour space (name, alias or role); auto: scene_linear for "
                           "EXR/HDR, the config's sRGB space otherwise (--in-colorspace)")),
          bind(&S::workingSpace,
               stringParam("working", "scene_linear",
                           "scene-linear working space (the config's scene_linear role by "
                           "default)")),
          bind(&S::outputSpace,
               stringParam("output", "auto",
                           "output colour space; auto: the working space for EXR/HDR, the "
                           "config's sRGB space otherwise (--out-colorspace)")),
          bind(&S::configPath,
               pathParam("config", "",
                         "path of an .ocio config; empty: $OCIO, else pluvia's built-in one")),
      });
  return table;
}

ColorSettings colorSettings(const Preset& p) {
  return colorTable().read(p);
}

}  // namespace pluvia
