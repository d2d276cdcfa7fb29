#include "stages/blur_settings.h"

namespace pluvia {

SectionSpec blurSection() {
  SectionSpec s;
  s.name = "blur";
  s.help = "Gaussian blur of the plate (refraction through rain).";
  s.inputs = {"image"};
  s.outputs = {"image"};
  s.params = {
      enabledParam(),
      numberParam("sigma_px", 0.0, {0.0, 100.0}, "px",
                  "standard deviation; 0 leaves the plate sharp"),
  };
  return s;
}

BlurSettings blurSettings(const Preset& p) {
  BlurSettings s;
  s.enabled = p.boolean("blur.enabled");
  s.sigmaPx = p.number("blur.sigma_px");
  return s;
}

}  // namespace pluvia
