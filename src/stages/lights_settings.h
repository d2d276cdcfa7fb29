#pragma once
// The preset's "lights" section: local lights of a night shot (street lamps, headlights, shop
// signs) that light the drops and glow in the wet air. Its parameter table and settings, read
// once from the preset.
#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "preset/preset.h"
#include "preset/ramp.h"
#include "preset/settings_table.h"

namespace pluvia {

// One light of lights.list. Positions and directions are in the camera's space (+X right, +Y
// up, looking along -Z: geometry/camera.h) or in the world's (+Y up, metres; the tracked
// camera's world when depth is COLMAP's), and then follow the camera.
struct LightSpec {
  bool spot = false;
  bool worldFrame = false;
  Ramp xMeters, yMeters, zMeters;
  std::array<double, 3> rgb{1, 1, 1};
  // Radiant intensity: irradiance intensity * rgb / d^2 at d metres, in the working space's
  // linear units (a lamp of 100 lights a white wall 10 m away to 1.0).
  Ramp intensity{100.0};
  double radiusMeters = 0.05;
  std::array<double, 3> direction{0, -1, 0};  // spot: its axis (normalised when used)
  Ramp halfAngleDeg{30.0};                    // spot: A
  double falloffQ = 0.0;                      // spot: q of I(theta)
  // A lamp found in the plate (lights.find): the plate already holds its image and the bloom the
  // camera gave it, so it lights the rain and the mist but gets no glare of its own.
  bool photographed = false;
};

// lights.glare: the veil bright sources spread over the picture (optics/glare.h).
enum class GlareMode { Auto, On, Off };

// lights.find: lamps looked for on a night plate, on any plate, or not at all.
enum class LampSearch { Auto, On, Off };

struct LightsSettings {
  bool enabled = true;
  std::vector<LightSpec> lights;
  bool halos = true;  // the glow and beams by single scattering
  bool drops = true;  // the drops lit by the lights
  // A light whose brightest halo pixel (unoccluded) is below this radiance is culled.
  double haloThresholdRadiance = 1e-3;
  // lights.find: the plate's clipped blobs become point lights (stages/plate_lights.h).
  LampSearch search = LampSearch::Auto;
  bool find = true;              // derived: enabled and not LampSearch::Off
  bool findOnDayPlates = false;  // derived: LampSearch::On looks on any plate, not only at night
  double findClipLevel = 0.95;
  int findMinAreaPx = 4;
  double findCoreGain = 100.0;
  GlareMode glare = GlareMode::Auto;
  nlohmann::json resolved;
};

// The section's table (`section()`: the StageInfo's spec) and its settings read from a
// resolved preset.
const SettingsTable<LightsSettings>& lightsTable();
LightsSettings lightsSettings(const Preset& preset);

}  // namespace pluvia
