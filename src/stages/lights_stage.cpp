// Lights: a night shot's local lights glow in the wet air. Per frame the preset's lights are
// placed in the camera's space (following the tracked camera when there is one), their halos
// and beams added to the plate by single scattering (optics/light_halos.h) through the rain's
// and the fog's extinction, occluded by the scene's depth, and handed on to the rain stage
// (FrameContext::lights), which lights its drops with them.
#include <fmt/format.h>

#include "optics/light_halos.h"
#include "optics/single_scattering.h"

#include "stages/clip_still.h"
#include "stages/depth_settings.h"
#include "stages/fog_settings.h"
#include "stages/lights_at_frame.h"
#include "stages/lights_settings.h"
#include "stages/plate_lights.h"
#include "stages/rain_medium.h"
#include "stages/rain_settings.h"
#include "stages/registry.h"
#include "util/log.h"

namespace pluvia {
namespace {

class LightsStage : public Stage {
 public:
  LightsStage(LightsSettings lights, RainSettings rain, FogSettings fog, double backdropMeters)
      : lights_(std::move(lights)),
        rain_(std::move(rain)),
        fog_(std::move(fog)),
        backdropMeters_(backdropMeters) {}

  void prepare(ClipContext& clip) override {
    path_ = clip.cameraPath;
    // The found lamps, once per clip: from the still, placed with the camera and the depth of
    // the clip's first frame, fixed in the world (a moving camera passes them); every chunk of a
    // farm render places them alike.
    if (lights_.find && !clip.foundLamps) {
      const std::vector<float> depth =
          clip.firstFrameDepth ? clip.firstFrameDepth() : std::vector<float>{};
      clip.foundLamps = findPlateLamps(clipStill(clip), lights_,
                                       path_.cameraAt(double(clip.clip->frames.front())),
                                       depth.empty() ? nullptr : &depth, backdropMeters_);
    }
    if (clip.foundLamps)
      for (const FoundLamp& lamp : *clip.foundLamps) lights_.lights.push_back(foundLampLight(lamp));
    // The halos' tables (a quarter of a second) only when there is a light to scatter.
    if (lights_.halos && !lights_.lights.empty())
      tables_ = std::make_unique<optics::ScatteringTables>();
    log::info(fmt::format("lights: {} lights{}", lights_.lights.size(),
                          clip.cameraTracked ? ", following the tracked camera" : ""));
  }

  void process(ClipContext&, FrameContext& frame) override {
    const double at = double(frame.frame);
    const Camera camera = path_.cameraAt(at);
    if (lights_.lights.empty()) return;
    frame.lights = lightsAtFrame(lights_, camera, at);
    frame.lightsExtinctionPerMeter = mediumAt(rain_, fog_, at).extinctionPerMeter();
    if (!tables_) return;
    const optics::HaloResult halos =
        optics::addHalos(frame.image, camera, frame.lights, frame.lightsExtinctionPerMeter,
                         *tables_, lights_.haloThresholdRadiance);
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
  double backdropMeters_;
  CameraPath path_;
  std::unique_ptr<optics::ScatteringTables> tables_;
  int lastCulled_ = 0;
};

}  // namespace

StageInfo lightsStageInfo() {
  return makeStageInfo(
      lightsTable().section(), lightsSettings,
      {.noOpReason = [](const LightsSettings& lights, const Preset& p) -> std::string {
         if (lights.lights.empty() && !lights.find)
           return "no lights (lights.list is empty, lights.find off): the light work is skipped";
         if (!lights.halos && !lights.drops) return "lights.halos and lights.drops are both off";
         // Halos need a medium and lit drops need drops: with neither rain nor fog there is
         // nothing for the lights to light.
         const FogSettings fog = fogSettings(p);
         const bool foggy = fog.enabled && fog.densityPerMeter > 0.0;
         if (!rainSettings(p).falls() && !foggy)
           return "no rain and no fog: nothing scatters the lights";
         return "";
       },
       .note =
           [](const LightsSettings& lights, const Preset&) {
             int spots = 0;
             for (const auto& l : lights.lights) spots += l.spot ? 1 : 0;
             return fmt::format(
                 "{} point lights, {} spotlights{}; halos {}, drops {}",
                 int(lights.lights.size()) - spots, spots,
                 lights.find ? ", and lamps looked for in the plate when the render prepares "
                               "(lights.find auto: clipped blobs, on a night plate only; the "
                               "render's log says how many it found)"
                             : "",
                 lights.halos ? "on" : "off", lights.drops ? "on" : "off");
           },
       .reads =
           [](const LightsSettings& lights, const Preset&) {
             std::vector<std::string> reads{"image", "depth", "camera"};
             // Lamps are found in the still and placed at the first frame's depth.
             if (lights.find) reads.insert(reads.end(), {"still", "first_frame_depth"});
             return reads;
           },
       .writes =
           [](const LightsSettings& lights, const Preset&) {
             std::vector<std::string> writes{"image", "lights"};
             if (lights.find) writes.push_back("found_lamps");
             return writes;
           },
       .create =
           [](const LightsSettings& lights, const Preset& p) {
             return std::make_unique<LightsStage>(lights, rainSettings(p), fogSettings(p),
                                                  depthSettings(p).backdropMeters);
           }});
}

}  // namespace pluvia
