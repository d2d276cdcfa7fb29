#include "stages/lights_settings.h"

#include <cmath>

#include <fmt/format.h>

#include "util/error.h"

namespace pluvia {
namespace {

ParamSpec listOfLights() {
  std::vector<ParamSpec> point{
      enumParam("frame", "camera", {"camera", "world"},
                "camera: position in the camera's space (+X right, +Y up, -Z ahead), moving with "
                "it; world: in the world's (+Y up), the tracked camera's world when it is tracked"),
      numberParam("x_m", 0.0, {-1e5, 1e5}, "m", "position x"),
      numberParam("y_m", 2.0, {-1e5, 1e5}, "m", "position y"),
      numberParam("z_m", -10.0, {-1e5, 1e5}, "m", "position z (negative ahead in camera space)"),
      colorParam("color", nlohmann::json::array({1.0, 0.8, 0.55}), "linear", "colour of the light"),
      numberParam("intensity", 100.0, {0.0, 1e9}, "radiance*m^2",
                  "radiant intensity: a surface facing the light d metres away receives "
                  "intensity * color / d^2 (100 lights a white wall 10 m away to 1.0)"),
      numberParam("radius_m", 0.05, {1e-4, 10.0}, "m", "the bulb's radius"),
  };
  allowKeyframes(point, {"x_m", "y_m", "z_m", "intensity"});
  std::vector<ParamSpec> spot = point;
  spot.push_back(numberParam("dir_x", 0.0, {-1.0, 1.0}, "", "axis x (normalised)"));
  spot.push_back(numberParam("dir_y", -1.0, {-1.0, 1.0}, "", "axis y (normalised)"));
  spot.push_back(numberParam("dir_z", 0.0, {-1.0, 1.0}, "", "axis z (normalised)"));
  spot.push_back(numberParam("half_angle_deg", 30.0, {0.01, 90.0}, "deg",
                             "cone half-angle A of I(theta) = I0 ((1 - q)(cos theta - cos A) / "
                             "(1 - cos A) + q) inside the cone (Huang et al.)"));
  spot.push_back(fractionParam("falloff_q", 0.0, "q of I(theta): 1 is a hard cone"));
  allowKeyframes(spot, {"x_m", "y_m", "z_m", "intensity", "half_angle_deg"});
  return listParam("list", nlohmann::json::array(), {{"point", point}, {"spot", spot}},
                   "local lights: point lights and spotlights");
}

double numberOr(const nlohmann::json& item, const char* key, double fallback) {
  return item.contains(key) ? item.at(key).get<double>() : fallback;
}

Ramp rampOr(const nlohmann::json& item, const char* key, double fallback) {
  return item.contains(key) ? Ramp::fromJson(item.at(key)) : Ramp(fallback);
}

}  // namespace

const SettingsTable<LightsSettings>& lightsTable() {
  using S = LightsSettings;
  static const SettingsTable<LightsSettings> table(
      {.name = "lights",
       .help = "Local lights at night: drops glint near them (the drop's transfer function, 1/d^2, "
               "the spot's cone), and each light glows in the wet air and a spot shows its beam "
               "(single scattering, Huang et al. 2006 after Sun et al. 2005), occluded by the "
               "scene's depth; the extinction is the rain's plus the fog's.",
       .inputs = {"image", "depth", "camera", "still", "first_frame_depth"},
       .outputs = {"image", "lights", "found_lamps"}},
      {
          bind(&S::enabled, enabledParam()),
          unbound<S>(listOfLights()),
          bind(&S::halos,
               booleanParam("halos", true, "the glow around lights and the beams of spots")),
          bind(&S::drops, booleanParam("drops", true, "the drops lit by the lights")),
          bind(&S::haloThresholdRadiance,
               numberParam("halo_threshold", 1e-3, {0.0, 1e3}, "radiance",
                           "a light whose brightest halo pixel is below this is culled (counted "
                           "in the log)")),
          bind(&S::search, "find",
               {{"auto", LampSearch::Auto}, {"on", LampSearch::On}, {"off", LampSearch::Off}},
               "auto: on a night plate (luminance median under 0.08, 90th percentile under 0.3: "
               "not a day plate in shade with a sunlit tenth), the clipped blobs in the "
               "dark (lamps) become point lights at the depth the depth stage gives around "
               "them, coloured like their unclipped rim, fixed in the world of the clip's "
               "camera; nothing clipped, none; on: on any plate; off: only lights.list"),
          bind(&S::findClipLevel,
               numberParam("find_level", 0.95, {0.01, 1e6}, "working-space",
                           "a pixel whose max channel is at least this is clipped (the white of a "
                           "display-referred file is 1.0)")),
          bind(&S::findMinAreaPx, numberParam("find_min_area_px", 4.0, {1.0, 1e6}, "px",
                                              "smallest clipped blob taken")),
          // A night exposure keeps the lit street (about 1 cd/m^2) near mid-grey; a lamp's
          // diffuser is 10^4 cd/m^2 and more. 100 (under 7 stops) is a conservative guess of what
          // the clip hides.
          bind(&S::findCoreGain,
               numberParam("find_core_gain", 100.0, {1.0, 1e6}, "",
                           "a found bulb's radiance (a clipped blob with a dark rim) is find_level "
                           "times this (its clipped core hides how bright it is): intensity = gain "
                           "* find_level * solid angle * distance^2; a clipped core inside its own "
                           "glow is taken at find_level")),
          bind(&S::glare, "glare",
               {{"auto", GlareMode::Auto}, {"on", GlareMode::On}, {"off", GlareMode::Off}},
               "the veil bright sources spread as the eye sees them (CIE 2002 disability glare), "
               "added after the rain: the lights' own and every pixel's light above 1.0; auto: on "
               "a frame with local lights whose veil 1 deg away could reach "
               "lights.halo_threshold; on: every frame; off: never"),
      });
  return table;
}

LightsSettings lightsSettings(const Preset& p) {
  LightsSettings s = lightsTable().read(p);
  for (const nlohmann::json& item : p.at("lights.list")) {
    LightSpec light;
    light.spot = item.at("type").get<std::string>() == "spot";
    light.worldFrame = item.value("frame", std::string("camera")) == "world";
    light.xMeters = rampOr(item, "x_m", 0.0);
    light.yMeters = rampOr(item, "y_m", 2.0);
    light.zMeters = rampOr(item, "z_m", -10.0);
    if (item.contains("color"))
      for (int c = 0; c < 3; ++c)
        light.rgb[size_t(c)] = item.at("color").at(size_t(c)).get<double>();
    light.intensity = rampOr(item, "intensity", 100.0);
    light.radiusMeters = numberOr(item, "radius_m", 0.05);
    light.direction = {numberOr(item, "dir_x", 0.0), numberOr(item, "dir_y", -1.0),
                       numberOr(item, "dir_z", 0.0)};
    // Said where the preset is read, so that `pluvia validate` says it as the render does.
    const double axisLength =
        std::hypot(light.direction[0], light.direction[1], light.direction[2]);
    if (light.spot && !(axisLength > 1e-9))
      throw Error(
          fmt::format("lights.list[{}]: a spot's axis (dir_x, dir_y, dir_z) = ({}, {}, {}) "
                      "has no length",
                      s.lights.size(), light.direction[0], light.direction[1], light.direction[2]),
          {"lights"});
    light.halfAngleDeg = rampOr(item, "half_angle_deg", 30.0);
    light.falloffQ = numberOr(item, "falloff_q", 0.0);
    s.lights.push_back(light);
  }
  s.find = s.enabled && s.search != LampSearch::Off;
  s.findOnDayPlates = s.search == LampSearch::On;
  return s;
}

}  // namespace pluvia
