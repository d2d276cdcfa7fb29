#include "pipeline/color_settings.h"

namespace pluvia {

SectionSpec colorSection() {
  SectionSpec s;
  s.name = "color";
  s.help = "OpenColorIO colour spaces at the two ends; everything between is scene-linear float.";
  s.params = {
      stringParam("input", "auto",
                  "input colour space; auto: linear-rec709 for EXR/HDR, sRGB otherwise"),
      stringParam("working", "linear-rec709", "scene-linear working space"),
      stringParam("output", "auto",
                  "output colour space; auto: linear-rec709 for EXR, sRGB otherwise"),
      stringParam("config", "", "path of an .ocio config; empty uses pluvia's built-in one"),
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
