#include "stages/splash_settings.h"

namespace pluvia {

SectionSpec splashSection() {
  SectionSpec s;
  s.name = "splash";
  s.help =
      "Splashes where drops strike surfaces facing up (from the depth plane): a crown and "
      "secondary droplets under gravity, at the rain's drop flux, shaded like the drops, "
      "depth-tested; their coverage is the \"splash\" AOV.";
  s.inputs = {"image", "depth", "environment"};
  s.outputs = {"image", "splash"};
  s.params = {
      enabledParam(),
      numberParam("min_diameter_mm", 0.5, {0.1, 6.0}, "mm",
                  "drops smaller than this make no visible splash"),
      numberParam("max_tilt_deg", 30.0, {0.0, 89.0}, "deg",
                  "surfaces tilted more than this from horizontal take no splashes"),
      numberParam("opacity", 1.0, {0.0, 1.0}, "", "scale on the splashes' coverage"),
  };
  return s;
}

SplashSettings splashSettings(const Preset& p) {
  SplashSettings s;
  s.enabled = p.boolean("splash.enabled");
  s.minDiameterMm = p.number("splash.min_diameter_mm");
  s.maxTiltDeg = p.number("splash.max_tilt_deg");
  s.opacity = p.number("splash.opacity");
  return s;
}

}  // namespace pluvia
