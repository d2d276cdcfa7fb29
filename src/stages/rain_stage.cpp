// Rain: particles carrying stroke mattes, drawn on the GPU through headless EGL, shaded by the
// environment (PRT) and composited over the plate (Wang et al. sections 3-4).
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "gpu/rain_renderer.h"
#include "optics/drop_shading.h"
#include "preset/camera_path_preset.h"
#include "rain/drop_simulation.h"
#include "rain/stroke_library.h"
#include "rain/thin_lens.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace pluvia {
namespace {

// The camera's lens (rain/thin_lens.h).
rain::ThinLens lensOf(const Preset& p, const Camera& camera) {
  return rain::ThinLens::of(camera.focalPx, camera.width, p.number("camera.sensor_width_mm"),
                            p.number("camera.focus_m"), p.number("camera.f_number"));
}

// rain.near_m, or with 0 the lens's: nearer drops are blurred over more than kNearBlurFraction
// of the frame's width, so faint that they are fog, not streaks (never nearer than
// kNearestMeters; a pinhole keeps the old 0.5 m).
double nearMeters(const Preset& p, const ClipContext& clip) {
  constexpr double kNearBlurFraction = 0.05, kNearestMeters = 0.3, kPinholeNearMeters = 0.5;
  const double given = p.number("rain.near_m");
  if (given > 0.0) return given;
  const rain::ThinLens lens = lensOf(p, clip.camera);
  if (!lens.defocuses()) return kPinholeNearMeters;
  return std::max(kNearestMeters,
                  lens.nearestWithBlurMeters(kNearBlurFraction * clip.camera.width));
}

rain::DropSimulationSettings simulationSettings(const Preset& p, const ClipContext& clip) {
  rain::DropSimulationSettings s;
  s.distribution = p.string("rain.distribution") == "gamma"
                       ? rain::SizeDistribution::Gamma
                       : rain::SizeDistribution::MarshallPalmer;
  s.velocityModel = p.string("rain.velocity") == "gunn_kinzer" ? rain::VelocityModel::GunnKinzer
                                                               : rain::VelocityModel::Atlas;
  s.minDiameterMm = p.number("rain.min_diameter_mm");
  s.nearMeters = nearMeters(p, clip);
  s.farMeters = p.number("rain.far_m");
  s.maxDrops = int64_t(p.number("rain.max_drops"));
  s.seed = uint64_t(p.number("rain.seed"));
  s.spreadMetersPerSecond = p.number("rain.spread_m_s");
  s.eddyIntensity = p.number("rain.wind.eddies");
  s.stepSeconds = 1.0 / clip.fps;
  // The simulation starts at rain.start_frame, whatever frame the plate starts at, so a plate
  // delivered with other handles gets the same rain on the same frame numbers.
  const int64_t clipFirst = clip.clip && !clip.clip->frames.empty() ? clip.clip->frames.front() : 0;
  s.firstFrame = std::min<int64_t>(int64_t(p.number("rain.start_frame")), clipFirst);
  s.lastFrame = clip.clip && !clip.clip->frames.empty() ? clip.clip->frames.back() : 0;
  s.wind.gustiness = p.number("rain.wind.gustiness");
  s.wind.turbulence = p.number("rain.wind.turbulence");
  s.wind.seed = s.seed;
  s.cells.count = int(p.number("rain.cells.count"));
  s.cells.radiusMeters = p.number("rain.cells.radius_m");
  s.cells.peakDensity = p.number("rain.cells.peak_density");
  s.cells.sizeScale = p.number("rain.cells.size_scale");
  s.cells.seed = s.seed;
  return s;
}

// Wind direction: degrees counter-clockwise from world +X seen from above (0 the camera's right
// for the default camera, 90 away from it), as in WindSettings.
rain::RainAtFrame rainAt(const Preset& p, double frame) {
  rain::RainAtFrame r;
  r.rateMmPerHour = p.number("rain.rate_mm_h", frame);
  r.densityScale = p.number("rain.density_scale", frame);
  r.sizeScale = p.number("rain.size_scale", frame);
  r.windSpeedMetersPerSecond = p.number("rain.wind.speed_m_s", frame);
  r.windDirectionDeg = p.number("rain.wind.dir_deg", frame);
  return r;
}

// Shutter: the angle when given (angle / 360 / fps), else the exposure time.
double exposureSeconds(const Preset& p, double fps, double frame) {
  const double angle = p.number("camera.shutter_angle_deg");
  return angle > 0.0 ? angle / 360.0 / fps : p.number("camera.exposure_s", frame);
}

// How the drops are shaded (src/optics/drop_shading.h): "default" looks the drop's radiance up
// in the environment convolved with the drop's transfer function; "paper" is Wang et al.'s 16
// SH coefficients plus c * B.
rain::ShadingParams dropShading(const Preset& p, const EquirectMap& environment) {
  const std::array<double, 3> eta =
      p.boolean("rain.dispersion")
          ? optics::kWaterEtaDispersion
          : std::array<double, 3>{optics::kWaterEta, optics::kWaterEta, optics::kWaterEta};
  rain::ShadingParams shading;
  const auto started = std::chrono::steady_clock::now();
  if (p.string("rain.shading") == "default") {
    shading.radianceMap = optics::buildDropRadianceMap(
        environment, optics::channelOptics(eta, optics::kDefaultTerms));
    shading.backgroundWeight = 0.0f;
  } else {
    const optics::PaperShading paper = optics::preparePaperShading(environment, eta);
    shading.shOrder = optics::kPaperShOrder;
    for (const auto& rgb : paper.environmentSh)
      shading.envSh.push_back({float(rgb[0]), float(rgb[1]), float(rgb[2])});
    // The GPU holds one transfer vector: the green channel's (dispersion shows in "default").
    for (int l = 0; l <= optics::kPaperShOrder; ++l) {
      shading.transferZonal.push_back(
          float(optics::zonalRotationFactor(l) * paper.zonal[1][size_t(l)]));
    }
    shading.backgroundWeight = float(p.number("rain.background_weight"));
  }
  log::info(fmt::format("rain: {} drop shading prepared in {:.0f} ms", p.string("rain.shading"),
                        secondsSince(started) * 1000.0));
  return shading;
}

class RainStage : public Stage {
 public:
  explicit RainStage(const Preset& p) : preset_(p) {}

  void prepare(ClipContext& clip) override {
    const Preset& p = preset_;
    fps_ = clip.fps;
    const CameraPath path =
        clip.trackedPath ? *clip.trackedPath : cameraPathFromPreset(p, clip.camera);
    if (clip.trackedPath)
      log::info(fmt::format("rain: camera tracked by COLMAP ({} keys, focal length {:.1f} px)",
                            path.keys().size(), path.cameraAt(0.0).focalPx));
    simulation_ = std::make_unique<rain::DropSimulation>(
        simulationSettings(p, clip), [path](double frame) { return path.cameraAt(frame); },
        [&p](double frame) { return rainAt(p, frame); });
    // Capped by rain.max_drops: the densest frame (rain cells included) draws fewer drops than
    // the physics asks for, thinned evenly.
    const double wanted = simulation_->wantedPoolSize();
    if (wanted > double(simulation_->poolSize()) + 0.5) {
      log::warning(fmt::format(
          "rain: the densest frame needs {:.0f} drops in the {:.0f} m^3 box; rain.max_drops = {} "
          "draws {:.0f} % of them there (the rest are left out: raise rain.max_drops or lower "
          "rain.far_m)",
          wanted, simulation_->boxVolumeCubicMeters(), simulation_->poolSize(),
          100.0 * double(simulation_->poolSize()) / wanted));
    }
    log::info(fmt::format("rain: drops from {:.2f} to {:g} m, simulated from frame {}",
                          simulation_->settings().nearMeters, p.number("rain.far_m"),
                          simulation_->settings().firstFrame));
    atlas_ = loadAtlas(clip);
    streakParams_.focusMeters = p.number("camera.focus_m");
    streakParams_.fNumber = p.number("camera.f_number");
    streakParams_.sensorWidthMm = p.number("camera.sensor_width_mm");
    streakParams_.fogDensityPerMeter = p.boolean("fog.enabled") ? p.number("fog.density") : 0.0;
    streakParams_.strokeCount = int(atlas_.rects.size());
    streakParams_.meanMatte = rain::meanMatte(atlas_);
    if (!clip.environment) throw Error("rain needs the lighting stage's environment", {"rain"});
    // One shading for the clip, or one per key environment of a looming camera.
    if (clip.environment->keys.empty()) shading_ = dropShading(p, clip.environment->radiance);
    for (const auto& [keyFrame, radiance] : clip.environment->keys)
      keyShading_.emplace_back(keyFrame, dropShading(p, radiance));
    renderer_ = std::make_unique<gpu::RainRenderer>(clip.camera.width, clip.camera.height);
    renderer_->setStrokeAtlas(atlas_);
    log::info(fmt::format("rain: {} drops in a {:.0f} m^3 box, {} strokes, GPU: {}",
                          simulation_->poolSize(), simulation_->boxVolumeCubicMeters(),
                          atlas_.rects.size(), renderer_->deviceDescription()));
  }

  void process(ClipContext& clip, FrameContext& frame) override {
    simulation_->advanceTo(frame.frame);
    streakParams_.exposureSeconds = exposureSeconds(preset_, fps_, double(frame.frame));
    streakParams_.opacity = preset_.number("rain.opacity", double(frame.frame));
    const auto streaks = simulation_->buildStreaks(streakParams_);
    if (keyShading_.empty()) {
      renderer_->render(frame.image, streaks, shading_);
    } else {
      renderer_->render(frame.image, streaks, shadingAt(frame.frame));
    }
  }

 private:
  rain::StrokeAtlas loadAtlas(ClipContext& clip) const {
    const std::string strokes = preset_.string("rain.strokes");
    if (strokes == "derain") {
      if (!clip.footageStrokes)
        throw Error("rain.strokes is \"derain\" but no strokes were extracted", {"rain"});
      return *clip.footageStrokes;
    }
    // "builtin": the library shipped with pluvia (assets/strokes/builtin.json); else a path.
    const std::string path = strokes == "builtin" ? rain::builtinStrokeLibraryPath() : strokes;
    try {
      return rain::loadStrokeLibrary(path).atlas;
    } catch (const Error& e) {
      throw Error(std::string("rain.strokes: ") + e.what(), {"rain", {}, e.context().file});
    }
  }

  // A looming camera's environment changes over the shot: the shading of the key frames around
  // `frame`, blended linearly (both terms are linear in the environment), the nearest key's
  // beyond the first and last.
  rain::ShadingParams shadingAt(int64_t frame) const {
    if (frame <= keyShading_.front().first) return keyShading_.front().second;
    if (frame >= keyShading_.back().first) return keyShading_.back().second;
    size_t next = 1;
    while (keyShading_[next].first < frame) ++next;
    const auto& [frameA, a] = keyShading_[next - 1];
    const auto& [frameB, b] = keyShading_[next];
    const float t = float(frame - frameA) / float(frameB - frameA);
    rain::ShadingParams mixed = a;
    for (size_t i = 0; i < mixed.radianceMap.rgb.size(); ++i)
      mixed.radianceMap.rgb[i] = (1 - t) * a.radianceMap.rgb[i] + t * b.radianceMap.rgb[i];
    for (size_t i = 0; i < mixed.envSh.size(); ++i)
      for (int c = 0; c < 3; ++c)
        mixed.envSh[i][size_t(c)] = (1 - t) * a.envSh[i][size_t(c)] + t * b.envSh[i][size_t(c)];
    return mixed;
  }

  const Preset& preset_;
  std::unique_ptr<rain::DropSimulation> simulation_;
  double fps_ = 24.0;
  rain::StrokeAtlas atlas_;
  rain::StreakSettings streakParams_;
  rain::ShadingParams shading_;
  std::vector<std::pair<int64_t, rain::ShadingParams>>
      keyShading_;  // empty: shading_ for every frame
  std::unique_ptr<gpu::RainRenderer> renderer_;
};

}  // namespace

StageInfo rainStageInfo() {
  StageInfo info;
  info.spec.name = "rain";
  info.spec.help =
      "Rain streaks on the GPU (headless EGL): drops by rate, stroke mattes, PRT shading, "
      "composite.";
  info.spec.inputs = {"image", "depth", "environment", "footage_strokes"};
  info.spec.outputs = {"image"};
  info.spec.params = {
      {"enabled", ParamType::Boolean, true, {}, {}, {}, "", "run this stage"},
      {"rate_mm_h",
       ParamType::Number,
       15.0,
       0.0,
       500.0,
       {},
       "mm/h",
       "rain rate; sets drop count and sizes (Marshall-Palmer)"},
      {"seed", ParamType::Integer, 1, 0, 4294967295.0, {}, "", "random seed; same seed, same rain"},
      {"strokes",
       ParamType::String,
       "builtin",
       {},
       {},
       {},
       "",
       "stroke library: builtin (cut from real rain, shipped), derain (cut from derain.input), or "
       "a LIBRARY.json written by `pluvia strokes`"},
      {"min_diameter_mm",
       ParamType::Number,
       0.8,
       0.05,
       5.99,  // the drop size distributions stop at 6 mm
       {},
       "mm",
       "smaller drops are left to the fog"},
      {"density_scale",
       ParamType::Number,
       1.0,
       0.0,
       100.0,
       {},
       "",
       "artist scale on the physical drop count"},
      {"size_scale",
       ParamType::Number,
       1.0,
       0.05,
       20.0,
       {},
       "",
       "artist scale on the drawn drop diameter"},
      {"opacity",
       ParamType::Number,
       1.0,
       0.0,
       100.0,
       {},
       "",
       "artist scale on the physical streak alpha"},
      {"near_m",
       ParamType::Number,
       0.0,
       0.0,
       100.0,
       {},
       "m",
       "nearest drops drawn; 0: from the lens (where the defocus blur reaches 5 % of the frame "
       "width, at least 0.3 m; 0.5 m for a pinhole)"},
      {"start_frame",
       ParamType::Integer,
       0,
       -1e9,
       1e9,
       {},
       "frame",
       "frame the simulation starts from (a pre-roll up to the plate's first frame), so plates "
       "with other handles get the same rain on the same frame numbers"},
      {"far_m", ParamType::Number, 15.0, 0.1, 1000.0, {}, "m", "farthest drops drawn"},
      {"max_drops",
       ParamType::Integer,
       100000,
       0,
       10000000,
       {},
       "drops",
       "cap on the simulated drops"},
      {"shading",
       ParamType::Enum,
       "default",
       {},
       {},
       {"default", "paper"},
       "",
       "default: environment convolved with the drop's transfer function (about 1 % from a "
       "ray-traced drop); "
       "paper: Wang et al.'s 16 SH coefficients + c B (about 50 %)"},
      {"dispersion",
       ParamType::Boolean,
       false,
       {},
       {},
       {},
       "",
       "per-channel refractive index 1.331 / 1.333 / 1.338"},
      {"background_weight",
       ParamType::Number,
       0.7,
       0.0,
       1.0,
       {},
       "",
       "c in C' = C + c B (Wang et al. Eq. 2); used by shading paper only"},
      {"distribution",
       ParamType::Enum,
       "marshall_palmer",
       {},
       {},
       {"marshall_palmer", "gamma"},
       "",
       "drop size distribution for the rate: Marshall-Palmer (1948) or a Gamma (Ulbrich)"},
      {"velocity",
       ParamType::Enum,
       "atlas",
       {},
       {},
       {"atlas", "gunn_kinzer"},
       "",
       "terminal velocity by diameter: Atlas et al. (1973) fit or Gunn-Kinzer (1949) table"},
      {"spread_m_s",
       ParamType::Number,
       0.0,
       0.0,
       20.0,
       {},
       "m/s",
       "artist spread: each drop's own random horizontal speed (std dev) on the wind"},
      {"wind.speed_m_s", ParamType::Number, 0.0, 0.0, 60.0, {}, "m/s", "horizontal wind speed"},
      {"wind.eddies",
       ParamType::Number,
       0.2,
       0.0,
       1.0,
       {},
       "",
       "small eddies: each drop's own horizontal speed, std dev as a fraction of the wind speed "
       "(turbulence intensity), so driven rain is not a parallel hatch"},
      {"wind.gustiness",
       ParamType::Number,
       0.0,
       0.0,
       1.0,
       {},
       "",
       "relative amplitude of gusts (a few seconds long) on the wind speed"},
      {"wind.turbulence",
       ParamType::Number,
       0.0,
       0.0,
       1.0,
       {},
       "",
       "unsteady 2-D wind field (stable fluids) over the ground: RMS over the wind speed"},
      {"cells.count",
       ParamType::Integer,
       0,
       0,
       64,
       {},
       "",
       "local high-density rain cells carried by the wind (Mizukami)"},
      {"cells.radius_m",
       ParamType::Number,
       10.0,
       0.1,
       1000.0,
       {},
       "m",
       "Gaussian radius of a cell"},
      {"cells.peak_density",
       ParamType::Number,
       4.0,
       1.0,
       100.0,
       {},
       "",
       "drop density at a cell's centre over the rate's"},
      {"cells.size_scale",
       ParamType::Number,
       1.3,
       1.0,
       3.0,
       {},
       "",
       "drop diameter at a cell's centre over the rate's (heavier drops)"},
      {"wind.dir_deg",
       ParamType::Number,
       0.0,
       -360.0,
       360.0,
       {},
       "deg",
       "direction the wind blows toward: 0 camera right, 90 away from the camera"},
  };
  // What the simulation reads frame by frame (drop_simulation.h's RainAtFrame, and the streaks'
  // opacity); the rest sizes the box, the pool and the random streams once for the shot.
  allowKeyframes(info.spec.params, {"rate_mm_h", "density_scale", "size_scale", "opacity",
                                    "wind.speed_m_s", "wind.dir_deg"});
  info.spec.increasing = {{"near_m", "far_m"}};
  info.noOpReason = [](const Preset& p) -> std::string {
    // A ramp is 0 throughout only when every key is (interpolation stays between keys).
    if (p.ramp("rain.rate_mm_h").maxValue() == 0.0) return "rate_mm_h is 0";
    if (p.ramp("rain.density_scale").maxValue() == 0.0) return "density_scale is 0";
    if (p.ramp("rain.opacity").maxValue() == 0.0) return "opacity is 0";
    if (p.number("rain.max_drops") == 0.0) return "max_drops is 0";
    return "";
  };
  info.reads = [](const Preset& p) {
    std::vector<std::string> reads{"image", "depth", "environment"};
    if (p.string("rain.strokes") == "derain") reads.push_back("footage_strokes");
    return reads;
  };
  info.create = [](const Preset& p) { return std::make_unique<RainStage>(p); };
  return info;
}

}  // namespace pluvia
