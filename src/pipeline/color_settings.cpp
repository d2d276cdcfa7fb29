#include "pipeline/color_settings.h"

namespace pluvia {

SectionSpec colorSection() {
  SectionSpec s;
  s.name = "color";
  s.help = "OpenColorIO colour spaces at the two ends; everything between is scene-linear float.";
  s.params = {
      stringParam("input", "auto",
                  "input colour space (name, alias or role); auto: scene_linear for EXR/HDR, the "
                  "config's sRGB space otherwise (--in-colorspace)"),
      stringParam("working", "scene_linear",
                  "scene-linear working space (the config's scene_linear role by default)"),
      stringParam("output", "auto",
                  "output colour space; auto: the working space for EXR/HDR, the config's sRGB "
                  "space otherwise (--out-colorspace)"),
      stringParam("config", "",
                  "path of an .ocio config; empty: $OCIO, else pluvia's built-in one"),
  };
  return s;
}

ColorSettings colorSettings(const Preset& p) {
  ColorSettings s;
  s.inputSpace = p.string("color.input");
  s.workingSpace = p.string("color.working");
  s.outputSpace = p.string("color.output");
  s.configPath = p.string("color.config");
  s.resolved = p.at("color");
  return s;
}

}  // namespace pluvia
