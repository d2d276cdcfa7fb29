#include "stages/fog_settings.h"

namespace pluvia {

SectionSpec fogSection() {
  SectionSpec s;
  s.name = "fog";
  s.help =
      "Homogeneous fog over the plate by depth: alpha = 1 - exp(-density * depth), toward the "
      "horizon's airlight; the sky keeps its own detail; no path longer than the rain's "
      "visibility.";
  s.inputs = {"image", "depth", "environment"};
  s.outputs = {"image"};
  s.params = {
      enabledParam(),
      numberParam("density", 0.0, {0.0, 10.0}, "1/m", "extinction per metre; 0 means no fog"),
      enumParam("color_source", "horizon", {"horizon", "average", "constant"},
                "fog colour (airlight): the environment's sky at the horizon, its average over "
                "the sphere, or fog.color"),
      colorParam("color", nlohmann::json::array({0.5, 0.5, 0.5}), "linear",
                 "fog colour when color_source is constant"),
  };
  return s;
}

FogSettings fogSettings(const Preset& p) {
  FogSettings s;
  s.enabled = p.boolean("fog.enabled");
  s.densityPerMeter = p.number("fog.density");
  s.colorSource = p.string("fog.color_source");
  s.constantRgb = p.color("fog.color");
  return s;
}

}  // namespace pluvia
