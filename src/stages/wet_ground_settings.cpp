#include "stages/wet_ground_settings.h"

#include "stages/clip_plate_rain.h"

namespace pluvia {

const SettingsTable<WetGroundSettings>& wetGroundTable() {
  using S = WetGroundSettings;
  static const SettingsTable<WetGroundSettings> table(
      {.name = "wet_ground",
       .help = "The ground the rain falls on (from the depth plane: surfaces facing up), wet: "
               "darkened as a rough surface under a film of water is (Lekner and Dorf 1988) and "
               "(with wet_ground.gloss) glossed with the environment it mirrors by Fresnel's "
               "reflectance; left out on a plate shot in rain; what it changes is the "
               "\"wet_ground\" AOV.",
       .inputs = {"image", "depth", "environment", "camera", "plate_rain"},
       .outputs = {"image", "wet_ground"}},
      {
          bind(&S::enabled, enabledParam()),
          bind(&S::overRain, overRainParam()),
          bind(&S::wetness, fractionParam("wetness", 1.0,
                                          "share of the ground under a film of water: 0 leaves "
                                          "it dry, 1 soaked")),
          bind(&S::gloss,
               fractionParam("gloss", 0.0,
                             "the film's mirror of the environment, times Fresnel's reflectance "
                             "(1) or less; 0 by default: the environment's sky is brighter than "
                             "the plate's ground implies, and the mirror whitened paving and "
                             "ghosted the people standing on it; none over the guessed depth "
                             "(depth.source auto)")),
          bind(&S::maxTiltDeg, numberParam("max_tilt_deg", 30.0, {0.0, 90.0}, "deg",
                                           "surfaces tilted up to this from level are fully wet")),
          bind(&S::fadeDeg, numberParam("fade_deg", 15.0, {0.0, 90.0}, "deg",
                                        "and dry again this much steeper (no seam where a "
                                        "guessed ground bends)")),
      });
  return table;
}

WetGroundSettings wetGroundSettings(const Preset& p) {
  return wetGroundTable().read(p);
}

}  // namespace pluvia
