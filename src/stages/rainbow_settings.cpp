#include "stages/rainbow_settings.h"

namespace pluvia {

SectionSpec rainbowSection() {
  SectionSpec s;
  s.name = "rainbow";
  s.help =
      "Primary and secondary rainbows of a sun behind the camera, scattered by the rain's drops "
      "(terms 3 and 4 of D(theta), per-channel eta), as bright as the rain's optical depth along "
      "each ray allows, hidden by nearer scene depth.";
  s.inputs = {"image", "depth", "environment"};
  s.outputs = {"image"};
  s.params = {
      enabledParam(),
      enumParam("sun", "environment", {"environment", "direction"},
                "where the sun is: the environment's brightest spot, or sun_elevation_deg and "
                "sun_azimuth_deg"),
      numberParam("sun_elevation_deg", 30.0, {-90.0, 90.0}, "deg",
                  "sun's elevation above the horizon (sun = direction)"),
      numberParam("sun_azimuth_deg", 180.0, {-360.0, 360.0}, "deg",
                  "sun's azimuth from world -Z (the default view) toward +X; 180 is behind the "
                  "camera (sun = direction)"),
      colorParam("sun_irradiance", nlohmann::json::array({3.0, 3.0, 3.0}), "linear",
                 "the sun's irradiance (sun = direction); pi lights a white surface facing it "
                 "to 1"),
      numberParam("shower_extent_m", 2000.0, {1.0, 100000.0}, "m",
                  "how far the rain reaches along a ray that meets no scene (the sky)"),
      numberParam("strength", 1.0, {0.0, 100.0}, "", "scale on the physical radiance"),
  };
  return s;
}

RainbowSettings rainbowSettings(const Preset& p) {
  RainbowSettings s;
  s.enabled = p.boolean("rainbow.enabled");
  s.sunSource = p.string("rainbow.sun");
  s.sunElevationDeg = p.number("rainbow.sun_elevation_deg");
  s.sunAzimuthDeg = p.number("rainbow.sun_azimuth_deg");
  s.sunIrradianceRgb = p.color("rainbow.sun_irradiance");
  s.showerExtentMeters = p.number("rainbow.shower_extent_m");
  s.strength = p.number("rainbow.strength");
  return s;
}

}  // namespace pluvia
