// Lights: a night shot's local lights glow in the wet air. Per frame the preset's lights are
// placed in the camera's space (following the tracked camera when there is one), their halos
// and beams added to the plate by single scattering (stages/local_lights.h) through the rain's
// and the fog's extinction, occluded by the scene's depth, and handed on to the rain stage
// (FrameContext::lights), which lights its drops with them.
#include <fmt/format.h>

#include <mutex>
#include "optics/single_scattering.h"
#include "pipeline/camera_settings.h"
#include "rain/drop_physics.h"

#include "stages/clip_still.h"
#include "stages/depth_settings.h"
#include "stages/fog_settings.h"
#include "stages/lights_settings.h"
#include "stages/local_lights.h"
#include "stages/plate_lights.h"
#include "stages/rain_settings.h"
#include "stages/registry.h"
#include "util/log.h"

namespace pluvia {
namespace {

// A clipped blob larger than this share of the frame is a clipped sky or window, not a lamp.
constexpr double kMaxLampShareOfFrame = 0.005;
// lights.find auto looks for lamps on night plates only: a day plate's clipped blobs are sky,
// clouds, white walls and glints, not sources. Night: the still's median luminance below this
// (scene-linear; about 35 % grey in sRGB). And a lamp is a source in the dark: its rim's mean
// luminance below this fraction of the clip level (a clipped patch of a lit wall has a bright rim).
constexpr double kNightMedianLuminance = 0.08;
constexpr double kLampRimOverClip = 0.4;

// The medium between the lights and the camera: the rain's extinction at the frame's rate plus
// the fog's density, per metre.
double extinctionPerMeter(const RainSettings& rain, const FogSettings& fog, double frame) {
  double beta = 0.0;
  if (rain.enabled) beta += rain::rainExtinctionPerMeter(rain.rateMmPerHour.valueAt(frame));
  if (fog.enabled) beta += fog.densityPerMeter;
  return beta;
}

class LightsStage : public Stage {
 public:
  LightsStage(LightsSettings lights, RainSettings rain, FogSettings fog, CameraSettings camera,
              double backdropMeters)
      : lights_(std::move(lights)),
        rain_(std::move(rain)),
        fog_(std::move(fog)),
        camera_(std::move(camera)),
        backdropMeters_(backdropMeters) {}

  void prepare(ClipContext& clip) override {
    path_ = clip.trackedPath ? *clip.trackedPath : camera_.path(clip.camera);
    if (lights_.find) {
      const Image& still = clipStill(clip);
      const double median = medianLuminance(still);
      if (lights_.findOnDayPlates || median < kNightMedianLuminance) {
        const double maxArea = kMaxLampShareOfFrame * still.width * still.height;
        for (PlateBlob& blob :
             findClippedBlobs(still, lights_.findClipLevel, lights_.findMinAreaPx))
          if (blob.areaPx <= maxArea &&
              blob.rimLuminance < kLampRimOverClip * lights_.findClipLevel)
            blobs_.push_back(std::move(blob));
        log::info(fmt::format(
            "lights: {} lights found in the plate (clipped blobs in the dark, max channel >= "
            "lights.find_level = {:g}){}",
            blobs_.size(), lights_.findClipLevel,
            blobs_.empty() && lights_.lights.empty()
                ? ": nothing to light, the light work is skipped"
                : ""));
      } else {
        log::info(fmt::format(
            "lights: no lamps looked for: the plate is not a night plate (median luminance "
            "{:.3f} >= {:g}; lights.find = on looks anyway)",
            median, kNightMedianLuminance));
      }
    }
    if (lights_.halos) tables_ = std::make_unique<optics::ScatteringTables>();
    log::info(fmt::format("lights: {} lights{}", lights_.lights.size() + blobs_.size(),
                          clip.trackedPath ? ", following the tracked camera" : ""));
  }

  void process(ClipContext&, FrameContext& frame) override {
    const double at = double(frame.frame);
    const Camera camera = path_.cameraAt(at);
    // The found lamps are placed once, with the first frame this stage sees (its camera and
    // depth), in the world: a moving camera then passes them.
    std::call_once(placed_, [&] {
      for (const PlateBlob& blob : blobs_) {
        lights_.lights.push_back(plateLight(blob, camera, frame.image.findPlane("depth"),
                                            backdropMeters_, lights_.findClipLevel,
                                            lights_.findCoreGain));
        const LightSpec& l = lights_.lights.back();
        log::info(fmt::format(
            "lights: found at ({:.1f}, {:.1f}) px, {} px: world ({:.2f}, "
            "{:.2f}, {:.2f}) m, colour ({:.2f}, {:.2f}, {:.2f}), intensity {:.3g}",
            blob.xPx, blob.yPx, blob.areaPx, l.xMeters.valueAt(0), l.yMeters.valueAt(0),
            l.zMeters.valueAt(0), l.rgb[0], l.rgb[1], l.rgb[2], l.intensity.valueAt(0)));
      }
    });
    if (lights_.lights.empty()) return;
    frame.lights = lightsAtFrame(lights_, camera, at);
    frame.lightsExtinctionPerMeter = extinctionPerMeter(rain_, fog_, at);
    if (!tables_) return;
    const HaloResult halos =
        addHalos(frame.image, camera, frame.lights, frame.lightsExtinctionPerMeter, *tables_,
                 lights_.haloThresholdRadiance);
    if (halos.culled != lastCulled_) {
      log::info(fmt::format(
          "lights: frame {}: {} of {} lights culled (halo below lights.halo_threshold = {:g} at "
          "extinction {:.3g} /m)",
          frame.frame, halos.culled, frame.lights.size(), lights_.haloThresholdRadiance,
          frame.lightsExtinctionPerMeter));
      lastCulled_ = halos.culled;
    }
  }

 private:
  LightsSettings lights_;
  RainSettings rain_;
  FogSettings fog_;
  CameraSettings camera_;
  double backdropMeters_;
  CameraPath path_;
  std::vector<PlateBlob> blobs_;
  std::once_flag placed_;
  std::unique_ptr<optics::ScatteringTables> tables_;
  int lastCulled_ = 0;
};

}  // namespace

StageInfo lightsStageInfo() {
  StageInfo info;
  info.spec = lightsTable().section();
  info.noOpReason = [](const Preset& p) -> std::string {
    const LightsSettings lights = lightsSettings(p);
    if (lights.lights.empty() && !lights.find)
      return "no lights (lights.list is empty, lights.find off): the light work is skipped";
    if (!lights.halos && !lights.drops) return "lights.halos and lights.drops are both off";
    // Halos need a medium and lit drops need drops: with neither rain nor fog there is nothing
    // for the lights to light.
    const FogSettings fog = fogSettings(p);
    const bool foggy = fog.enabled && fog.densityPerMeter > 0.0;
    if (!rainSettings(p).falls() && !foggy)
      return "no rain and no fog: nothing scatters the lights";
    return "";
  };
  info.note = [](const Preset& p) -> std::string {
    const LightsSettings lights = lightsSettings(p);
    int spots = 0;
    for (const auto& l : lights.lights) spots += l.spot ? 1 : 0;
    return fmt::format(
        "{} point lights, {} spotlights{}; halos {}, drops {}", int(lights.lights.size()) - spots,
        spots,
        lights.find ? ", and lamps looked for in the plate at render time (lights.find auto: "
                      "clipped blobs; none clipped, no light work)"
                    : "",
        lights.halos ? "on" : "off", lights.drops ? "on" : "off");
  };
  info.reads = [](const Preset&) { return std::vector<std::string>{"image", "depth"}; };
  info.create = [](const Preset& p) {
    return std::make_unique<LightsStage>(lightsSettings(p), rainSettings(p), fogSettings(p),
                                         cameraSettings(p), depthSettings(p).backdropMeters);
  };
  return info;
}

}  // namespace pluvia
