#pragma once
// The preset's "rain" section: its parameter table and its settings, read once from the preset.
// Keyframable values are Ramps (preset/ramp.h), read at each frame.
#include <cstdint>
#include <string>

#include "preset/preset.h"
#include "preset/ramp.h"
#include "preset/settings_table.h"
#include "rain/drop_physics.h"

namespace pluvia {

// rain.shading: the drop's transfer function over the environment, or Wang et al.'s SH.
enum class DropShading { Default, Paper };

// Where the rain's strokes come from (rain.strokes): the library shipped with pluvia, the strokes
// the derain stage cuts from rain footage, or a LIBRARY.json file.
enum class StrokeSource { Builtin, Derain, File };

struct RainSettings {
  bool enabled = true;
  Ramp rateMmPerHour{15.0};
  uint64_t seed = 1;
  std::string strokes = "builtin";                    // "builtin", "derain" or a LIBRARY.json path
  StrokeSource strokeSource = StrokeSource::Builtin;  // derived from strokes
  double minDiameterMm = 0.8;
  Ramp densityScale{1.0};  // artist scales on the physical drop count, diameter and alpha
  Ramp sizeScale{1.0};
  Ramp opacity{1.0};
  double nearMeters = 0.0;  // 0: from the lens
  int64_t startFrame = 0;
  double farMeters = 0.0;  // 0: from the camera (rain/rain_depth.h)
  int64_t maxDrops = 100000;
  double lodPx = 0.0;  // drops narrower than this (px) drawn as lines (far_drop_lines.h); 0: none
  DropShading shading = DropShading::Default;
  bool dispersion = false;
  double backgroundWeight = 0.7;  // DropShading::Paper only
  rain::SizeDistribution distribution = rain::SizeDistribution::MarshallPalmer;
  rain::VelocityModel velocity = rain::VelocityModel::Atlas;
  double spreadMetersPerSecond = 0.0;
  struct Wind {
    Ramp speedMetersPerSecond{0.0};
    Ramp directionDeg{0.0};  // toward: 0 camera right, 90 away from the camera
    double eddies = 0.2;     // fractions of the wind speed
    double gustiness = 0.0;
    double turbulence = 0.0;
  } wind;
  struct Cells {
    int count = 0;
    double radiusMeters = 10.0;
    double peakDensity = 4.0;
    double sizeScale = 1.3;
  } cells;

  // Whether any rain falls during the shot: the section on and its rate above 0 at some key (the
  // stages that need drops to scatter, splash or light are no-ops otherwise).
  bool falls() const { return enabled && rateMmPerHour.maxValue() > 0.0; }
};

// The section's table (`section()`: the StageInfo's spec) and its settings read from a
// resolved preset.
const SettingsTable<RainSettings>& rainTable();
RainSettings rainSettings(const Preset& preset);

// How deep a camera of focal length `focalPx` sees this rain as streaks (rain/rain_depth.h), for
// the shot's heaviest rate and largest drops; 0 when no rain falls.
double streakDepthMeters(const RainSettings& rain, double focalPx);

}  // namespace pluvia
