#include "stages/rain_settings.h"

namespace pluvia {

SectionSpec rainSection() {
  SectionSpec s;
  s.name = "rain";
  s.help =
      "Rain streaks on the GPU (headless EGL): drops by rate, stroke mattes, PRT shading, "
      "composite.";
  s.inputs = {"image", "depth", "environment", "footage_strokes"};
  s.outputs = {"image"};
  s.params = {
      enabledParam(),
      numberParam("rate_mm_h", 15.0, {0.0, 500.0}, "mm/h",
                  "rain rate; sets drop count and sizes (Marshall-Palmer)"),
      integerParam("seed", 1, {0, 4294967295.0}, "", "random seed; same seed, same rain"),
      stringParam("strokes", "builtin",
                  "stroke library: builtin (cut from real rain, shipped), derain (cut from "
                  "derain.input), or a LIBRARY.json written by `pluvia strokes`"),
      // The drop size distributions stop at 6 mm.
      numberParam("min_diameter_mm", 0.8, {0.05, 5.99}, "mm", "smaller drops are left to the fog"),
      numberParam("density_scale", 1.0, {0.0, 100.0}, "",
                  "artist scale on the physical drop count"),
      numberParam("size_scale", 1.0, {0.05, 20.0}, "", "artist scale on the drawn drop diameter"),
      numberParam("opacity", 1.0, {0.0, 100.0}, "", "artist scale on the physical streak alpha"),
      numberParam("near_m", 0.0, {0.0, 100.0}, "m",
                  "nearest drops drawn; 0: from the lens (where the defocus blur reaches 5 % of "
                  "the frame width, at least 0.3 m; 0.5 m for a pinhole)"),
      integerParam("start_frame", 0, {-1e9, 1e9}, "frame",
                   "frame the simulation starts from (a pre-roll up to the plate's first frame), "
                   "so plates with other handles get the same rain on the same frame numbers"),
      numberParam("far_m", 15.0, {0.1, 1000.0}, "m", "farthest drops drawn"),
      integerParam("max_drops", 100000, {0, 10000000}, "drops", "cap on the simulated drops"),
      numberParam("lod_px", 0.0, {0.0, 10.0}, "px",
                  "level of detail: drops whose projected diameter is under this are drawn as "
                  "single-pixel lines carrying their coverage, not textured streaks; 0: every drop "
                  "a streak"),
      enumParam("shading", "default", {"default", "paper"},
                "default: environment convolved with the drop's transfer function (about 1 % "
                "from a ray-traced drop); paper: Wang et al.'s 16 SH coefficients + c B (about "
                "50 %)"),
      booleanParam("dispersion", false, "per-channel refractive index 1.331 / 1.333 / 1.338"),
      numberParam("background_weight", 0.7, {0.0, 1.0}, "",
                  "c in C' = C + c B (Wang et al. Eq. 2); used by shading paper only"),
      enumParam("distribution", "marshall_palmer", {"marshall_palmer", "gamma"},
                "drop size distribution for the rate: Marshall-Palmer (1948) or a Gamma "
                "(Ulbrich)"),
      enumParam("velocity", "atlas", {"atlas", "gunn_kinzer"},
                "terminal velocity by diameter: Atlas et al. (1973) fit or Gunn-Kinzer (1949) "
                "table"),
      numberParam("spread_m_s", 0.0, {0.0, 20.0}, "m/s",
                  "artist spread: each drop's own random horizontal speed (std dev) on the wind"),
      numberParam("wind.speed_m_s", 0.0, {0.0, 60.0}, "m/s", "horizontal wind speed"),
      numberParam("wind.eddies", 0.2, {0.0, 1.0}, "",
                  "small eddies: each drop's own horizontal speed, std dev as a fraction of the "
                  "wind speed (turbulence intensity), so driven rain is not a parallel hatch"),
      numberParam("wind.gustiness", 0.0, {0.0, 1.0}, "",
                  "relative amplitude of gusts (a few seconds long) on the wind speed"),
      numberParam("wind.turbulence", 0.0, {0.0, 1.0}, "",
                  "unsteady 2-D wind field (stable fluids) over the ground: RMS over the wind "
                  "speed"),
      integerParam("cells.count", 0, {0, 64}, "",
                   "local high-density rain cells carried by the wind (Mizukami)"),
      numberParam("cells.radius_m", 10.0, {0.1, 1000.0}, "m", "Gaussian radius of a cell"),
      numberParam("cells.peak_density", 4.0, {1.0, 100.0}, "",
                  "drop density at a cell's centre over the rate's"),
      numberParam("cells.size_scale", 1.3, {1.0, 3.0}, "",
                  "drop diameter at a cell's centre over the rate's (heavier drops)"),
      numberParam("wind.dir_deg", 0.0, {-360.0, 360.0}, "deg",
                  "direction the wind blows toward: 0 camera right, 90 away from the camera"),
  };
  // What the simulation reads frame by frame (drop_simulation.h's RainAtFrame, and the streaks'
  // opacity); the rest sizes the box, the pool and the random streams once for the shot.
  allowKeyframes(s.params, {"rate_mm_h", "density_scale", "size_scale", "opacity", "wind.speed_m_s",
                            "wind.dir_deg"});
  s.increasing = {{"near_m", "far_m"}};
  return s;
}

RainSettings rainSettings(const Preset& p) {
  RainSettings s;
  s.enabled = p.boolean("rain.enabled");
  s.rateMmPerHour = p.ramp("rain.rate_mm_h");
  s.seed = uint64_t(p.number("rain.seed"));
  s.strokes = p.string("rain.strokes");
  s.minDiameterMm = p.number("rain.min_diameter_mm");
  s.densityScale = p.ramp("rain.density_scale");
  s.sizeScale = p.ramp("rain.size_scale");
  s.opacity = p.ramp("rain.opacity");
  s.nearMeters = p.number("rain.near_m");
  s.startFrame = int64_t(p.number("rain.start_frame"));
  s.farMeters = p.number("rain.far_m");
  s.maxDrops = int64_t(p.number("rain.max_drops"));
  s.lodPx = p.number("rain.lod_px");
  s.shading = p.string("rain.shading");
  s.dispersion = p.boolean("rain.dispersion");
  s.backgroundWeight = p.number("rain.background_weight");
  s.distribution = p.string("rain.distribution") == "gamma"
                       ? rain::SizeDistribution::Gamma
                       : rain::SizeDistribution::MarshallPalmer;
  s.velocity = p.string("rain.velocity") == "gunn_kinzer" ? rain::VelocityModel::GunnKinzer
                                                          : rain::VelocityModel::Atlas;
  s.spreadMetersPerSecond = p.number("rain.spread_m_s");
  s.wind.speedMetersPerSecond = p.ramp("rain.wind.speed_m_s");
  s.wind.directionDeg = p.ramp("rain.wind.dir_deg");
  s.wind.eddies = p.number("rain.wind.eddies");
  s.wind.gustiness = p.number("rain.wind.gustiness");
  s.wind.turbulence = p.number("rain.wind.turbulence");
  s.cells.count = int(p.number("rain.cells.count"));
  s.cells.radiusMeters = p.number("rain.cells.radius_m");
  s.cells.peakDensity = p.number("rain.cells.peak_density");
  s.cells.sizeScale = p.number("rain.cells.size_scale");
  return s;
}

}  // namespace pluvia
