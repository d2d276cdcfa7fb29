// Fog: rain too far away to show as streaks reads as fog (Wang et al. section 5, "Rain Fog"):
// alpha = 1 - exp(-density * depth), toward the airlight: the environment's sky at the horizon
// (where a long path through the rain looks, Environment::horizonRgb), or a constant. The sky keeps
// its own colour and detail (it is already the airlight at infinity, image/ops.h), and no path
// through the fog is longer than the visibility through the rain (rain/drop_physics.h).
// fog.model = skylight instead scatters the environment itself (or a CIE overcast sky without
// one) into each view ray through the rain and the fog (stages/skylight_fog.h): a table of
// in-scattered radiance per direction, built once per clip.
#include <fmt/format.h>

#include "image/ops.h"
#include "optics/skylight_scattering.h"
#include "stages/clip_plate_rain.h"
#include "stages/depth_grading.h"
#include "stages/fog_settings.h"
#include "stages/lamp_keeping.h"
#include "stages/rain_medium.h"
#include "stages/rain_settings.h"
#include "stages/registry.h"
#include "stages/skylight_fog.h"
#include "util/error.h"
#include "util/log.h"

namespace pluvia {
namespace {

class FogStage : public Stage {
 public:
  FogStage(FogSettings fog, RainSettings rain) : fog_(std::move(fog)), rain_(std::move(rain)) {}

  void prepareAhead(ClipContext& clip) override {
    if (!fog_.overRain) startPlateRainCheck(clip);
  }

  void prepare(ClipContext& clip) override {
    leftOut_ = leaveOutOnRainedPlate(clip, "fog", fog_.overRain);
    if (leftOut_) return;
    findNightPlate(clip);
    rgb_ = fog_.constantRgb;
    if (fog_.model == FogModel::Skylight) {
      prepareSkylight(clip);  // fog.color: the CIE sky's zenith without an environment
      return;
    }
    if (fog_.colorSource == FogColorSource::Constant) return;
    if (!clip.environment)
      throw Error("fog takes its colour from the environment, which was not computed", {"fog"});
    const bool average = fog_.colorSource == FogColorSource::Average;
    rgb_ = average ? clip.environment->averageRgb : clip.environment->horizonRgb;
    log::info(fmt::format("fog: airlight {:.4f} {:.4f} {:.4f} ({})", rgb_[0], rgb_[1], rgb_[2],
                          average ? "average" : "horizon"));
  }

  void process(ClipContext& clip, FrameContext& frame) override {
    if (leftOut_) return;
    const GradingAov aov(frame.image, "fog");
    const KeptLamps lamps(frame.image, frameLampShare(clip, frame));
    addFog(frame);
    lamps.restore(frame.image);
    aov.finish(frame.image, {});
  }

 private:
  void addFog(FrameContext& frame) const {
    // The rain of this frame bounds the path: its visibility (about 2 km at 15 mm/h).
    const RainMedium medium = mediumAt(rain_, fog_, double(frame.frame));
    if (skylight_) {
      optics::SkylightMedium skylight;
      skylight.rainExtinctionPerMeter = medium.rainExtinctionPerMeter;
      skylight.fogPerMeter = medium.fogPerMeter;
      applySkylightFog(frame.image, path_.cameraAt(double(frame.frame)), *skylight_, skylight,
                       medium.rainVisibilityMeters);
      return;
    }
    ops::fog(frame.image, float(medium.fogPerMeter), rgb_, float(medium.rainVisibilityMeters));
  }

  void prepareSkylight(ClipContext& clip) {
    path_ = clip.cameraPath;
    const EquirectMap sky = clip.environment
                                ? clip.environment->radiance
                                : optics::cieOvercastSky(4 * fog_.skylightTableWidth, rgb_);
    skylight_ = optics::buildSkylightTable(sky, fog_.skylightTableWidth);
    const std::array<float, 3>& mean = skylight_->meanRadiance;
    log::info(fmt::format("fog: skylight from {}, table {}x{}, mean radiance {:.4f} {:.4f} {:.4f}",
                          clip.environment ? "the environment" : "a CIE overcast sky",
                          fog_.skylightTableWidth, fog_.skylightTableWidth / 2, mean[0], mean[1],
                          mean[2]));
  }

  FogSettings fog_;
  RainSettings rain_;
  CameraPath path_;
  std::optional<optics::SkylightTable> skylight_;
  std::array<float, 3> rgb_{0, 0, 0};
  bool leftOut_ = false;
};

}  // namespace

StageInfo fogStageInfo() {
  return makeStageInfo(
      fogTable().section(), fogSettings,
      {.noOpReason = [](const FogSettings& fog, const Preset& p) -> std::string {
         // Skylight fog scatters through the rain as well: no-op only without fog
         // and rain.
         if (fog.model == FogModel::Skylight) {
           // Any frame with rain (a ramp may start dry), as the other stages ask.
           return fog.densityPerMeter == 0.0 && !rainSettings(p).falls()
                      ? "density is 0 and no rain"
                      : "";
         }
         return fog.densityPerMeter == 0.0 ? "density is 0" : "";
       },
       .note = [](const FogSettings& fog,
                  const Preset&) { return rainedPlateNote("fog", fog.overRain); },
       .reads =
           [](const FogSettings& fog, const Preset&) {
             std::vector<std::string> reads{"image", "depth", "camera"};
             if (fog.model == FogModel::Skylight || fog.colorSource != FogColorSource::Constant)
               reads.push_back("environment");
             if (!fog.overRain) reads.push_back("plate_rain");
             return reads;
           },
       .cachedWork =
           [](const FogSettings& fog, const Preset&, const ClipInfo& clip,
              const std::string& framesKey, const ArtifactCache& cache) {
             return cachedPlateRainNote(clip, framesKey, cache, fog.overRain);
           },
       .create = [](const FogSettings& fog,
                    const Preset& p) { return std::make_unique<FogStage>(fog, rainSettings(p)); }});
}

}  // namespace pluvia
