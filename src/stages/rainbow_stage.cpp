// Rainbow: the bows of a sun behind the camera in the rain (stages/rainbow_render.h), added to
// the plate after the fog and before the rain's streaks. The sun is given, or found in the
// environment the lighting stage computed; the colours come from water's dispersion.
#include <fmt/format.h>

#include "optics/drop_shading.h"
#include "optics/rainbow.h"
#include "pipeline/camera_settings.h"
#include "rain/drop_physics.h"
#include "stages/fog_settings.h"
#include "stages/rain_medium.h"
#include "stages/rain_settings.h"
#include "stages/rainbow_render.h"
#include "stages/rainbow_settings.h"
#include "stages/registry.h"
#include "util/log.h"

namespace pluvia {
namespace {

// The plan's view: the preset's camera over a 16:9 frame.
constexpr int kPlanWidth = 1920, kPlanHeight = 1080;

class RainbowStage : public Stage {
 public:
  RainbowStage(RainbowSettings bow, RainSettings rain, FogSettings fog)
      : bow_(std::move(bow)), rain_(std::move(rain)), fog_(std::move(fog)) {}

  void prepare(ClipContext& clip) override {
    path_ = clip.cameraPath;
    if (bow_.sunSource == RainbowSun::Direction) {
      sun_ = Sun{sunDirection(bow_.sunElevationDeg, bow_.sunAzimuthDeg),
                 {bow_.sunIrradianceRgb[0], bow_.sunIrradianceRgb[1], bow_.sunIrradianceRgb[2]}};
    } else {
      if (!clip.environment)
        throw Error("rainbow.sun = environment needs the lighting stage's environment",
                    {"rainbow"});
      sun_ = findSun(clip.environment->radiance);
      if (!sun_) {
        log::info(
            "rainbow: left out: the environment has no sun (nothing stands out "
            "of its mean)");
        return;
      }
    }
    const std::string hidden = rainbowHiddenReason(path_.cameraAt(0.0), sun_->direction);
    if (!hidden.empty()) log::info("rainbow: " + hidden);
    // The median volume diameter of Marshall-Palmer rain at the first frame's rate sets the
    // bows' width (D0 = 3.67 / Lambda).
    const double rate = std::max(rain_.rateMmPerHour.valueAt(0.0), 0.01);
    optics::RainbowProfileSettings profile;
    profile.dropDiameterMm = 3.67 / rain::marshallPalmerSlopePerMm(rate);
    profiles_ = optics::rainbowProfiles(optics::kWaterEtaDispersion, profile);
    log::info(fmt::format("rainbow: sun at elevation {:.1f} deg, irradiance {:.3f} {:.3f} {:.3f}",
                          std::asin(sun_->direction.y()) * 180.0 / M_PI, sun_->irradianceRgb[0],
                          sun_->irradianceRgb[1], sun_->irradianceRgb[2]));
  }

  void process(ClipContext&, FrameContext& frame) override {
    if (!sun_) return;
    RainbowVolume volume;
    const RainMedium medium = mediumAt(rain_, fog_, double(frame.frame));
    volume.rainExtinctionPerMeter = medium.rainExtinctionPerMeter;
    volume.fogExtinctionPerMeter = medium.fogPerMeter;
    volume.showerExtentMeters = bow_.showerExtentMeters;
    volume.strength = bow_.strength;
    addRainbow(frame.image, path_.cameraAt(double(frame.frame)), *sun_, profiles_, volume);
  }

 private:
  RainbowSettings bow_;
  RainSettings rain_;
  FogSettings fog_;
  CameraPath path_;
  std::optional<Sun> sun_;
  std::array<optics::RainbowProfile, 3> profiles_;
};

}  // namespace

StageInfo rainbowStageInfo() {
  return makeStageInfo(
      rainbowTable().section(), rainbowSettings,
      {.noOpReason = [](const RainbowSettings& bow, const Preset& p) -> std::string {
         if (!rainSettings(p).falls()) return "no rain to scatter";
         if (bow.strength == 0.0) return "strength is 0";
         if (bow.sunSource != RainbowSun::Direction) return "";
         const CameraSettings camera = cameraSettings(p);
         return rainbowHiddenReason(camera.path(camera.base(kPlanWidth, kPlanHeight)).cameraAt(0.0),
                                    sunDirection(bow.sunElevationDeg, bow.sunAzimuthDeg));
       },
       .note = [](const RainbowSettings& bow, const Preset&) -> std::string {
         if (bow.sunSource != RainbowSun::Environment) return "";
         return "the sun is looked for in the environment when the render prepares: left "
                "out there if none stands out of its mean (the render's log says which)";
       },
       .reads =
           [](const RainbowSettings& bow, const Preset&) {
             std::vector<std::string> reads{"image", "depth", "camera"};
             if (bow.sunSource == RainbowSun::Environment) reads.push_back("environment");
             return reads;
           },
       .create =
           [](const RainbowSettings& bow, const Preset& p) {
             return std::make_unique<RainbowStage>(bow, rainSettings(p), fogSettings(p));
           }});
}

}  // namespace pluvia
