// Rain: particles carrying stroke mattes, drawn on the GPU through headless EGL, shaded by the
// environment (PRT) and composited over the plate (Wang et al. sections 3-4).
#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "gpu/rain_renderer.h"
#include "optics/drop_local_light.h"
#include "optics/drop_shading.h"
#include "pipeline/camera_settings.h"
#include "pipeline/plate_lens.h"
#include "rain/drop_glint.h"
#include "rain/drop_simulation.h"
#include "rain/stroke_library.h"
#include "rain/thin_lens.h"
#include "stages/cached_drop_radiance.h"
#include "stages/clip_still.h"
#include "stages/fog_settings.h"
#include "stages/lights_settings.h"
#include "stages/plate_lights.h"
#include "stages/plate_shutter.h"
#include "stages/rain_plate_blur.h"
#include "stages/rain_settings.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/log.h"
#include "util/parallel.h"
#include "util/timer.h"

namespace pluvia {
namespace {

// The camera's lens (rain/thin_lens.h).
rain::ThinLens lensOf(const CameraSettings& settings, const Camera& camera) {
  return rain::ThinLens::of(camera.focalPx, camera.width, settings.sensorWidthMm,
                            settings.focusMeters, settings.fNumber);
}

// rain.near_m, or with 0 the lens's: nearer drops are blurred over more than kNearBlurFraction
// of the frame's width, so faint that they are fog, not streaks (never nearer than
// kNearestMeters; a pinhole keeps the old 0.5 m).
double nearMeters(const RainSettings& rain, const CameraSettings& camera, const ClipContext& clip) {
  constexpr double kNearBlurFraction = 0.05, kNearestMeters = 0.3, kPinholeNearMeters = 0.5;
  if (rain.nearMeters > 0.0) return rain.nearMeters;
  const rain::ThinLens lens = lensOf(camera, clip.camera);
  if (!lens.defocuses()) return kPinholeNearMeters;
  return std::max(kNearestMeters,
                  lens.nearestWithBlurMeters(kNearBlurFraction * clip.camera.width));
}

// rain.far_m, or with 0: by day the depth out to which the camera that filmed the plate sees this
// rain as streaks (rain/rain_depth.h: from its focal length in pixels, a proxy's scaled back to
// the full frame, for the shot's heaviest rate and largest drops), and at least twice the nearest
// drops' depth. That rule was measured on daylight footage, where a drop's contrast is its sky's;
// on a night plate a drop near a lamp stands out of the dark far beyond it (Garg and Nayar: the
// visible depth grows with the drop's contrast over the noise), so the rain is drawn to
// kNightFarMeters (the depth every preset drew to before the rule, not a measured one) for the
// lamps' glints, and the drops far from the lamps stay dark.
constexpr double kNightFarMeters = 8.0;
double farMeters(const RainSettings& rain, const ClipContext& clip, double nearMeters,
                 bool nightPlate) {
  if (rain.farMeters > 0.0) return rain.farMeters;
  if (nightPlate) return std::max(2.0 * nearMeters, kNightFarMeters);
  return std::max(2.0 * nearMeters,
                  streakDepthMeters(rain, clip.camera.focalPx * clip.filmedScale));
}

rain::DropSimulationSettings simulationSettings(const RainSettings& rain,
                                                const CameraSettings& camera,
                                                const ClipContext& clip, bool nightPlate) {
  rain::DropSimulationSettings s;
  s.distribution = rain.distribution;
  s.velocityModel = rain.velocity;
  s.minDiameterMm = rain.minDiameterMm;
  s.nearMeters = nearMeters(rain, camera, clip);
  s.farMeters = farMeters(rain, clip, s.nearMeters, nightPlate);
  s.maxDrops = rain.maxDrops;
  s.seed = rain.seed;
  s.spreadMetersPerSecond = rain.spreadMetersPerSecond;
  s.eddyIntensity = rain.wind.eddies;
  s.stepSeconds = 1.0 / clip.fps;
  // The simulation starts at rain.start_frame, whatever frame the plate starts at, so a plate
  // delivered with other handles gets the same rain on the same frame numbers.
  const int64_t clipFirst = clip.clip && !clip.clip->frames.empty() ? clip.clip->frames.front() : 0;
  s.firstFrame = std::min<int64_t>(rain.startFrame, clipFirst);
  s.lastFrame = clip.clip && !clip.clip->frames.empty() ? clip.clip->frames.back() : 0;
  s.wind.gustiness = rain.wind.gustiness;
  s.wind.turbulence = rain.wind.turbulence;
  s.wind.seed = s.seed;
  s.cells.count = rain.cells.count;
  s.cells.radiusMeters = rain.cells.radiusMeters;
  s.cells.peakDensity = rain.cells.peakDensity;
  s.cells.sizeScale = rain.cells.sizeScale;
  s.cells.seed = s.seed;
  return s;
}

// Wind direction: degrees counter-clockwise from world +X seen from above (0 the camera's right
// for the default camera, 90 away from it), as in WindSettings.
rain::RainAtFrame rainAt(const RainSettings& rain, double frame) {
  rain::RainAtFrame r;
  r.rateMmPerHour = rain.rateMmPerHour.valueAt(frame);
  r.densityScale = rain.densityScale.valueAt(frame);
  r.sizeScale = rain.sizeScale.valueAt(frame);
  r.windSpeedMetersPerSecond = rain.wind.speedMetersPerSecond.valueAt(frame);
  r.windDirectionDeg = rain.wind.directionDeg.valueAt(frame);
  return r;
}

// How the drops are shaded (src/optics/drop_shading.h): "default" looks the drop's radiance up
// in the environment convolved with the drop's transfer function; "paper" is Wang et al.'s 16
// SH coefficients plus c * B.
rain::ShadingParams dropShading(ClipContext& clip, const RainSettings& rain,
                                const EquirectMap& environment) {
  const std::array<double, 3> eta =
      rain.dispersion
          ? optics::kWaterEtaDispersion
          : std::array<double, 3>{optics::kWaterEta, optics::kWaterEta, optics::kWaterEta};
  rain::ShadingParams shading;
  const auto started = std::chrono::steady_clock::now();
  const bool byTransfer = rain.shading == DropShading::Default;
  if (byTransfer) {
    shading.radianceMap =
        cachedDropRadianceMap(clip, environment, optics::channelOptics(eta, optics::kDefaultTerms));
    shading.backgroundWeight = 0.0f;
  } else {
    const optics::PaperShading paper = optics::preparePaperShading(environment, eta);
    shading.shOrder = optics::kPaperShOrder;
    for (const auto& rgb : paper.environmentSh)
      shading.envSh.push_back({float(rgb[0]), float(rgb[1]), float(rgb[2])});
    // The GPU holds one transfer vector: the green channel's (dispersion shows in the default).
    for (int l = 0; l <= optics::kPaperShOrder; ++l) {
      shading.transferZonal.push_back(
          float(optics::zonalRotationFactor(l) * paper.zonal[1][size_t(l)]));
    }
    shading.backgroundWeight = float(rain.backgroundWeight);
  }
  log::info(fmt::format("rain: {} drop shading prepared in {:.0f} ms",
                        byTransfer ? "default" : "paper", secondsSince(started) * 1000.0));
  return shading;
}

class RainStage : public Stage {
 public:
  RainStage(RainSettings rain, CameraSettings camera, FogSettings fog, bool litDrops)
      : rain_(std::move(rain)),
        camera_(std::move(camera)),
        fog_(std::move(fog)),
        litDrops_(litDrops) {}

  void prepare(ClipContext& clip) override {
    fps_ = clip.fps;
    camera_.checkExposureFits(fps_);
    resolvePlateShutter(camera_, clip, "rain");
    camera_ = withPlateLens(camera_, clip.plateLens);
    log::info("rain: lens " + lensLine(camera_, clip.plateLens));
    const bool nightPlate = isNightPlate(plateLuminance(clipStill(clip)));
    const CameraPath path = clip.cameraPath;
    path_ = path;
    // D(theta) per steradian for drops lit by the local lights (lights stage), 512 bins in
    // cos(theta): the paper's water, 9 terms.
    if (litDrops_) transfer_ = optics::binTransfer(optics::DropOptics{}, 512);
    if (clip.cameraTracked)
      log::info(fmt::format("rain: camera tracked by COLMAP ({} keys, focal length {:.1f} px)",
                            path.keys().size(), path.cameraAt(0.0).focalPx));
    simulation_ = std::make_unique<rain::DropSimulation>(
        simulationSettings(rain_, camera_, clip, nightPlate),
        [path](double frame) { return path.cameraAt(frame); },
        [this](double frame) { return rainAt(rain_, frame); });
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
    log::info(fmt::format(
        "rain: drops from {:.2f} to {:.3g} m{}, simulated in segments of {} frames from frame {}",
        simulation_->settings().nearMeters, simulation_->settings().farMeters,
        rain_.farMeters > 0.0 ? ""
        : nightPlate          ? " (rain.far_m 0 on a night plate: lamp-lit drops glint far)"
                              : " (rain.far_m 0: as deep as this camera sees the rain as streaks)",
        simulation_->settings().segmentFrames, simulation_->settings().firstFrame));
    atlas_ = loadAtlas(clip);
    streakParams_.focusMeters = camera_.focusMeters;
    streakParams_.fNumber = camera_.fNumber;
    streakParams_.sensorWidthMm = camera_.sensorWidthMm;
    streakParams_.fogDensityPerMeter = fog_.enabled ? fog_.densityPerMeter : 0.0;
    streakParams_.strokeCount = int(atlas_.rects.size());
    streakParams_.lodPx = rain_.lodPx;
    streakParams_.meanMatte = rain::meanMatte(atlas_);
    streakParams_.strokeQuadScale = rain::strokeQuadScales(atlas_);
    plateBlurPx_ = rainSofteningPx(clip, streakParams_.minWidthPx, nightPlate);
    if (!clip.environment) throw Error("rain needs the lighting stage's environment", {"rain"});
    // One shading for the clip, or one per key environment of a looming camera.
    if (clip.environment->keys.empty())
      shading_ = dropShading(clip, rain_, clip.environment->radiance);
    for (const auto& [keyFrame, radiance] : clip.environment->keys)
      keyShading_.emplace_back(keyFrame, dropShading(clip, rain_, radiance));
    renderer_ = std::make_unique<gpu::RainRenderer>(clip.camera.width, clip.camera.height);
    renderer_->setStrokeAtlas(atlas_);
    log::info(fmt::format("rain: {} drops in a {:.0f} m^3 box, {} strokes, GPU: {}",
                          simulation_->poolSize(), simulation_->boxVolumeCubicMeters(),
                          atlas_.rects.size(), renderer_->deviceDescription()));
  }

  void process(ClipContext& clip, FrameContext& frame) override {
    simulation_->advanceTo(frame.frame);
    streakParams_.exposureSeconds = camera_.exposureSecondsAt(fps_, double(frame.frame));
    streakParams_.opacity = rain_.opacity.valueAt(double(frame.frame));
    auto streaks = simulation_->buildStreaks(streakParams_, &farStreaks_);
    if (litDrops_ && !frame.lights.empty()) {
      lightDrops(streaks, frame);
      lightDrops(farStreaks_, frame);
    }
    if (plateBlurPx_ > 0.0) plate_ = frame.image.rgba;
    if (keyShading_.empty()) {
      renderer_->render(frame.image, streaks, shading_, farStreaks_);
    } else {
      renderer_->render(frame.image, streaks, shadingAt(frame.frame), farStreaks_);
    }
    blurRainOverPlate(frame.image, plate_, plateBlurPx_);
  }

 private:
  rain::StrokeAtlas loadAtlas(ClipContext& clip) const {
    if (rain_.strokeSource == StrokeSource::Derain) {
      if (!clip.footageStrokes)
        throw Error("rain.strokes is \"derain\" but no strokes were extracted", {"rain"});
      return *clip.footageStrokes;
    }
    // The library shipped with pluvia (assets/strokes/builtin.json), or a file.
    const std::string path = rain_.strokeSource == StrokeSource::Builtin
                                 ? rain::builtinStrokeLibraryPath()
                                 : rain_.strokes;
    try {
      return rain::loadStrokeLibrary(path).atlas;
    } catch (const Error& e) {
      throw Error(std::string("rain.strokes: ") + e.what(), {"rain", {}, e.context().file});
    }
  }

  // Each drop's radiance from the frame's local lights (optics/drop_local_light.h), at the drop's
  // place in camera space: along its view ray, at its z-depth; its glint beaded by the drop's
  // oscillation as the light that lights it most sees it (rain/drop_glint.h).
  void lightDrops(std::vector<rain::StreakInstance>& streaks, const FrameContext& frame) const {
    const Eigen::Matrix3d cameraFromWorld =
        path_.cameraAt(double(frame.frame)).worldFromCamera.transpose();
    const Eigen::Vector3d upCamera = cameraFromWorld * Eigen::Vector3d::UnitY();
    forEachIndex(streaks.size(), [&](size_t i) {
      rain::StreakInstance& streak = streaks[i];
      const Eigen::Vector3d view =
          cameraFromWorld * Eigen::Vector3d(streak.viewX, streak.viewY, streak.viewZ);
      const double distance = streak.depthMeters / std::max(1e-6, -view.z());
      const std::array<double, 3> drop{view.x() * distance, view.y() * distance,
                                       view.z() * distance};
      const optics::DropLocalLight local =
          optics::dropLocalRadiance(transfer_, frame.lights, frame.lightsExtinctionPerMeter, drop,
                                    {view.x(), view.y(), view.z()});
      streak.localR = local.rgb[0];
      streak.localG = local.rgb[1];
      streak.localB = local.rgb[2];
      rain::shapeGlint(streak, local.towardsBrightest, {-view.x(), -view.y(), -view.z()},
                       {upCamera.x(), upCamera.y(), upCamera.z()});
    });
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

  RainSettings rain_;
  CameraSettings camera_;
  FogSettings fog_;
  std::unique_ptr<rain::DropSimulation> simulation_;
  double fps_ = 24.0;
  rain::StrokeAtlas atlas_;
  rain::StreakSettings streakParams_;
  std::vector<rain::StreakInstance> farStreaks_;  // under rain.lod_px: drawn as lines
  rain::ShadingParams shading_;
  std::vector<std::pair<int64_t, rain::ShadingParams>>
      keyShading_;  // empty: shading_ for every frame
  std::unique_ptr<gpu::RainRenderer> renderer_;
  // The plate camera's blur beyond the drawn streaks' (stages/rain_plate_blur.h), and the frame
  // before the rain is drawn over it; 0 and empty where the plate's blur is not measured.
  double plateBlurPx_ = 0.0;
  std::vector<float> plate_;
  bool litDrops_ = false;
  CameraPath path_;
  optics::TransferTable transfer_;
};

}  // namespace

StageInfo rainStageInfo() {
  return makeStageInfo(
      rainTable().section(), rainSettings,
      {.noOpReason = [](const RainSettings& rain, const Preset&) -> std::string {
         // A ramp is 0 throughout only when every key is (interpolation stays between keys).
         if (rain.rateMmPerHour.maxValue() == 0.0) return "rate_mm_h is 0";
         if (rain.densityScale.maxValue() == 0.0) return "density_scale is 0";
         if (rain.opacity.maxValue() == 0.0) return "opacity is 0";
         if (rain.maxDrops == 0) return "max_drops is 0";
         return "";
       },
       .reads =
           [](const RainSettings& rain, const Preset& p) {
             std::vector<std::string> reads{"image", "depth", "environment", "camera"};
             if (rain.strokeSource == StrokeSource::Derain) reads.push_back("footage_strokes");
             if (lightsSettings(p).drops) reads.push_back("lights");
             // A night plate is told from a day one by its still (for rain.far_m 0 and for
             // the plate's blur on the rain).
             reads.push_back("still");
             return reads;
           },
       // Every frame names the seed of its rain.
       .frameMetadata = [](const RainSettings& rain,
                           const Preset&) -> std::map<std::string, std::string> {
         return {{"pluvia:seed", std::to_string(int64_t(rain.seed))}};
       },
       .create =
           [](const RainSettings& rain, const Preset& p) {
             const LightsSettings lights = lightsSettings(p);
             return std::make_unique<RainStage>(
                 rain, cameraSettings(p), fogSettings(p),
                 lights.enabled && lights.drops && (!lights.lights.empty() || lights.find));
           }});
}

}  // namespace pluvia
