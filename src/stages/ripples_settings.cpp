#include "stages/ripples_settings.h"

namespace pluvia {

const SettingsTable<RipplesSettings>& ripplesTable() {
  using S = RipplesSettings;
  static const SettingsTable<RipplesSettings> table(
      {.name = "ripples",
       .help = "Rings on level ground where drops strike it (from the depth plane): capillary-"
               "gravity rings spreading at the minimum phase speed (0.231 m/s), damped as on "
               "film-covered water, mirroring the plate's own reflection displaced (the "
               "environment where the plate does not show it) with Fresnel's reflectance; drawn "
               "where a pixel resolves their crests; what they change is the \"ripples\" AOV.",
       .inputs = {"image", "depth", "environment", "camera"},
       .outputs = {"image", "ripples"}},
      {
          bind(&S::enabled,
               booleanParam("enabled", false,
                            "run this stage (off by default: the rings read too strong "
                            "yet, and cost 11 times the rain stage)")),
          bind(&S::minDiameterMm, numberParam("min_diameter_mm", 0.5, {0.1, 6.0}, "mm",
                                              "drops smaller than this raise no ring")),
          bind(&S::maxTiltDeg,
               numberParam("max_tilt_deg", 5.0, {0.0, 30.0}, "deg",
                           "ground tilted more than this from level holds no standing water")),
      });
  return table;
}

RipplesSettings ripplesSettings(const Preset& p) {
  return ripplesTable().read(p);
}

}  // namespace pluvia
