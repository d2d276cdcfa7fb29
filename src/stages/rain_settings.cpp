#include "stages/rain_settings.h"

#include "rain/rain_depth.h"

namespace pluvia {

// The Ramp members (rate, the artist scales, the wind's speed and direction) are keyframable:
// what the simulation reads frame by frame (drop_simulation.h's RainAtFrame, and the streaks'
// opacity); the rest sizes the box, the pool and the random streams once for the shot.
const SettingsTable<RainSettings>& rainTable() {
  using S = RainSettings;
  using Wind = RainSettings::Wind;
  using Cells = RainSettings::Cells;
  static const SettingsTable<RainSettings> table(
      {.name = "rain",
       .help = "Rain streaks on the GPU (headless EGL): drops by rate, stroke mattes, PRT shading, "
               "composite.",
       .inputs = {"image", "depth", "environment", "footage_strokes", "camera", "lights", "still"},
       .outputs = {"image"},
       .increasing = {{"near_m", "far_m"}}},
      {
          bind(&S::enabled, enabledParam()),
          bind(&S::rateMmPerHour, numberParam("rate_mm_h", 15.0, {0.0, 500.0}, "mm/h",
                                              "rain rate; sets drop count and sizes "
                                              "(Marshall-Palmer)")),
          bind(&S::seed,
               integerParam("seed", 1, {0, 4294967295.0}, "", "random seed; same seed, same rain")),
          bind(&S::strokes,
               pathParam("strokes", "builtin",
                         "stroke library: builtin (cut from real rain, shipped), derain (cut "
                         "from derain.input), or a LIBRARY.json written by `pluvia strokes`",
                         {"builtin", "derain"})),
          // The drop size distributions stop at 6 mm.
          bind(&S::minDiameterMm, numberParam("min_diameter_mm", 0.8, {0.05, 5.99}, "mm",
                                              "smaller drops are left to the fog")),
          bind(&S::densityScale, numberParam("density_scale", 1.0, {0.0, 100.0}, "",
                                             "artist scale on the physical drop count")),
          bind(&S::sizeScale, numberParam("size_scale", 1.0, {0.05, 20.0}, "",
                                          "artist scale on the drawn drop diameter")),
          bind(&S::opacity, numberParam("opacity", 1.0, {0.0, 100.0}, "",
                                        "artist scale on the physical streak alpha")),
          bind(&S::nearMeters,
               numberParam("near_m", 0.0, {0.0, 100.0}, "m",
                           "nearest drops drawn; 0: from the lens (where the defocus blur reaches "
                           "5 % of the frame width, at least 0.3 m; 0.5 m for a pinhole)")),
          bind(&S::startFrame,
               integerParam("start_frame", 0, {-1e9, 1e9}, "frame",
                            "frame the simulation counts its 24-frame segments from, so plates "
                            "with other handles get the same rain on the same frame numbers (any "
                            "frame costs at most 23 steps)")),
          bind(&S::farMeters,
               numberParam("far_m", 0.0, {0.0, 1000.0}, "m",
                           "farthest drops drawn; 0: as deep as the camera sees rain as streaks "
                           "(twice the depth at which the rain's median drop is one pixel wide: "
                           "1.9 m at 8 mm/h on a 640 px wide 50 deg view, 5.7 m at 1920 px; "
                           "the fog stands for the rain beyond; 8 m on a night plate, where "
                           "lamp-lit drops glint far)")),
          bind(&S::maxDrops, integerParam("max_drops", 100000, {0, 10000000}, "drops",
                                          "cap on the simulated drops")),
          bind(&S::lodPx,
               numberParam("lod_px", 0.0, {0.0, 10.0}, "px",
                           "level of detail: drops whose projected diameter is under this are "
                           "drawn as single-pixel lines carrying their coverage, not textured "
                           "streaks; 0: every drop a streak")),
          bind(&S::shading, "shading",
               {{"default", DropShading::Default}, {"paper", DropShading::Paper}},
               "default: environment convolved with the drop's transfer function (about 1 % from "
               "a ray-traced drop); paper: Wang et al.'s 16 SH coefficients + c B (about 50 %)"),
          bind(&S::dispersion, booleanParam("dispersion", false,
                                            "per-channel refractive index 1.331 / 1.333 / 1.338")),
          bind(&S::backgroundWeight,
               fractionParam("background_weight", 0.7,
                             "c in C' = C + c B (Wang et al. Eq. 2); used by shading paper only")),
          bind(&S::distribution, "distribution",
               {{"marshall_palmer", rain::SizeDistribution::MarshallPalmer},
                {"gamma", rain::SizeDistribution::Gamma}},
               "drop size distribution for the rate: Marshall-Palmer (1948) or a Gamma (Ulbrich)"),
          bind(&S::velocity, "velocity",
               {{"atlas", rain::VelocityModel::Atlas},
                {"gunn_kinzer", rain::VelocityModel::GunnKinzer}},
               "terminal velocity by diameter: Atlas et al. (1973) fit or Gunn-Kinzer (1949) "
               "table"),
          bind(&S::spreadMetersPerSecond,
               numberParam("spread_m_s", 0.0, {0.0, 20.0}, "m/s",
                           "artist spread: each drop's own random horizontal speed (std dev) on "
                           "the wind")),
          bind(&S::wind, &Wind::speedMetersPerSecond,
               numberParam("wind.speed_m_s", 0.0, {0.0, 60.0}, "m/s", "horizontal wind speed")),
          bind(
              &S::wind, &Wind::eddies,
              fractionParam("wind.eddies", 0.2,
                            "small eddies: each drop's own horizontal speed, std dev as a fraction "
                            "of the wind speed (turbulence intensity), so driven rain is not a "
                            "parallel hatch")),
          bind(&S::wind, &Wind::gustiness,
               fractionParam("wind.gustiness", 0.0,
                             "relative amplitude of gusts (a few seconds long) on the wind speed")),
          bind(
              &S::wind, &Wind::turbulence,
              fractionParam("wind.turbulence", 0.0,
                            "unsteady 2-D wind field (stable fluids) over the ground: RMS over the "
                            "wind speed")),
          bind(&S::cells, &Cells::count,
               integerParam("cells.count", 0, {0, 64}, "",
                            "local high-density rain cells carried by the wind (Mizukami)")),
          bind(
              &S::cells, &Cells::radiusMeters,
              numberParam("cells.radius_m", 10.0, {0.1, 1000.0}, "m", "Gaussian radius of a cell")),
          bind(&S::cells, &Cells::peakDensity,
               numberParam("cells.peak_density", 4.0, {1.0, 100.0}, "",
                           "drop density at a cell's centre over the rate's")),
          bind(&S::cells, &Cells::sizeScale,
               numberParam("cells.size_scale", 1.3, {1.0, 3.0}, "",
                           "drop diameter at a cell's centre over the rate's (heavier drops)")),
          bind(&S::wind, &Wind::directionDeg,
               numberParam("wind.dir_deg", 0.0, {-360.0, 360.0}, "deg",
                           "direction the wind blows toward: 0 camera right, 90 away from the "
                           "camera")),
      });
  return table;
}

double streakDepthMeters(const RainSettings& rain, double focalPx) {
  const double rate = rain.rateMmPerHour.maxValue(), sizeScale = rain.sizeScale.maxValue();
  return rate > 0.0 && sizeScale > 0.0 ? rain::streakDepthMeters(focalPx, rate, sizeScale) : 0.0;
}

RainSettings rainSettings(const Preset& p) {
  RainSettings rain = rainTable().read(p);
  rain.strokeSource = rain.strokes == "builtin"  ? StrokeSource::Builtin
                      : rain.strokes == "derain" ? StrokeSource::Derain
                                                 : StrokeSource::File;
  return rain;
}

}  // namespace pluvia
