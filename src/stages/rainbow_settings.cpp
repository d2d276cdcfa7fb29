#include "stages/rainbow_settings.h"

namespace pluvia {

const SettingsTable<RainbowSettings>& rainbowTable() {
  using S = RainbowSettings;
  static const SettingsTable<RainbowSettings> table(
      {.name = "rainbow",
       .help = "Primary and secondary rainbows of a sun behind the camera, scattered by the rain's "
               "drops (terms 3 and 4 of D(theta), per-channel eta), as bright as the rain's "
               "optical depth along each ray allows, hidden by nearer scene depth.",
       .inputs = {"image", "depth", "environment", "camera"},
       .outputs = {"image"}},
      {
          bind(&S::enabled, enabledParam()),
          bind(&S::sunSource, "sun",
               {{"environment", RainbowSun::Environment}, {"direction", RainbowSun::Direction}},
               "where the sun is: the environment's brightest spot, or sun_elevation_deg and "
               "sun_azimuth_deg"),
          bind(&S::sunElevationDeg,
               numberParam("sun_elevation_deg", 30.0, {-90.0, 90.0}, "deg",
                           "sun's elevation above the horizon (sun = direction)")),
          bind(&S::sunAzimuthDeg,
               numberParam("sun_azimuth_deg", 180.0, {-360.0, 360.0}, "deg",
                           "sun's azimuth from world -Z (the default view) toward +X; 180 is "
                           "behind the camera (sun = direction)")),
          bind(&S::sunIrradianceRgb,
               colorParam("sun_irradiance", nlohmann::json::array({3.0, 3.0, 3.0}), "linear",
                          "the sun's irradiance (sun = direction); pi lights a white surface "
                          "facing it to 1")),
          bind(&S::showerExtentMeters,
               numberParam("shower_extent_m", 2000.0, {1.0, 100000.0}, "m",
                           "how far the rain reaches along a ray that meets no scene (the sky)")),
          bind(&S::strength,
               numberParam("strength", 1.0, {0.0, 100.0}, "", "scale on the physical radiance")),
      });
  return table;
}

RainbowSettings rainbowSettings(const Preset& p) {
  return rainbowTable().read(p);
}

}  // namespace pluvia
