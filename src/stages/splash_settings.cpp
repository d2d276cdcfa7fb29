#include "stages/splash_settings.h"

namespace pluvia {

const SettingsTable<SplashSettings>& splashTable() {
  using S = SplashSettings;
  static const SettingsTable<SplashSettings> table(
      {.name = "splash",
       .help = "Splashes where drops strike surfaces facing up (from the depth plane): a crown and "
               "secondary droplets under gravity, at the rain's drop flux, shaded like the drops, "
               "depth-tested; their coverage is the \"splash\" AOV.",
       .inputs = {"image", "depth", "environment", "camera", "still"},
       .outputs = {"image", "splash"}},
      {
          bind(&S::enabled, enabledParam()),
          bind(&S::minDiameterMm, numberParam("min_diameter_mm", 0.5, {0.1, 6.0}, "mm",
                                              "drops smaller than this make no visible splash")),
          bind(&S::maxTiltDeg,
               numberParam("max_tilt_deg", 30.0, {0.0, 89.0}, "deg",
                           "surfaces tilted more than this from horizontal take no splashes")),
          bind(&S::opacity, fractionParam("opacity", 1.0, "scale on the splashes' coverage")),
          bind(&S::minSizePx,
               numberParam("min_size_px", 2.0, {0.0, 100.0}, "px",
                           "surfaces so far that a 3 mm drop's crown (12 mm across) spans fewer "
                           "pixels take no splashes: beyond, a splash is a sub-pixel speck that "
                           "costs time and shows nothing; 0 splashes everywhere")),
          bind(&S::splatter,
               booleanParam("splatter", false,
                            "flash a splatter texture flat on the surface at each impact (Wang et "
                            "al.'s splatters, made per impact); off by default: a look, not "
                            "physics, and it speckles the whole wet ground on a locked-off plate")),
          bind(&S::splatterMs,
               numberParam("splatter_ms", 40.0, {1.0, 1000.0}, "ms",
                           "how long a splatter shows after its impact (a frame at 25 fps)")),
      });
  return table;
}

SplashSettings splashSettings(const Preset& p) {
  return splashTable().read(p);
}

}  // namespace pluvia
