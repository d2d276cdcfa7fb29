#include "stages/fog_settings.h"

#include <fmt/format.h>

#include "stages/clip_plate_rain.h"
#include "util/error.h"

namespace pluvia {

const SettingsTable<FogSettings>& fogTable() {
  using S = FogSettings;
  static const SettingsTable<FogSettings> table(
      {.name = "fog",
       .help =
           "Homogeneous fog over the plate by depth: alpha = 1 - exp(-density * depth), toward "
           "the horizon's airlight; the sky keeps its own detail; no path longer than the rain's "
           "visibility. model = skylight instead scatters the environment into every view ray "
           "through the rain and the fog (Huang et al. 2006, Eq. 5-6): per pixel L_in(view) (1 - "
           "exp(-sigma d)) over the plate times exp(-sigma d), sigma = the rain's scattering + "
           "density.",
       .inputs = {"image", "depth", "environment", "camera", "plate_rain"},
       .outputs = {"image"}},
      {
          bind(&S::enabled, enabledParam()),
          bind(&S::overRain, overRainParam()),
          bind(&S::model, "model",
               {{"exponential", FogModel::Exponential}, {"skylight", FogModel::Skylight}},
               "exponential: one airlight colour (color_source); skylight: the environment (or a "
               "CIE overcast sky of zenith radiance fog.color without one) scattered by the "
               "rain's drops and the fog per view direction"),
          bind(&S::densityPerMeter, numberParam("density", 0.0, {0.0, 10.0}, "1/m",
                                                "extinction per metre; 0 means no fog")),
          bind(&S::colorSource, "color_source",
               {{"horizon", FogColorSource::Horizon},
                {"average", FogColorSource::Average},
                {"constant", FogColorSource::Constant}},
               "fog colour (airlight): the environment's sky at the horizon, its average over the "
               "sphere, or fog.color"),
          bind(&S::constantRgb,
               colorParam("color", nlohmann::json::array({0.5, 0.5, 0.5}), "linear",
                          "fog colour when color_source is constant; the CIE sky's zenith "
                          "radiance for model skylight without an environment")),
          bind(&S::skylightTableWidth,
               integerParam("skylight_table", 64, {8, 512}, "texels",
                            "width of the skylight model's in-scattering table (width x width/2 "
                            "view directions; pluvia report fog: error against size)")),
      });
  return table;
}

FogSettings fogSettings(const Preset& p) {
  FogSettings s = fogTable().read(p);
  if (s.skylightTableWidth % 2 != 0)
    throw Error(fmt::format("fog.skylight_table must be even, got {}", s.skylightTableWidth),
                {"fog"});
  return s;
}

}  // namespace pluvia
