// Wet ground: the plate's surfaces facing up, wet (rain/wet_ground.h), before the rain falls in
// front of them; on a plate shot in rain its ground is wet already and the stage leaves itself
// out unless wet_ground.over_rain. Over a guessed depth (depth.source auto) the guess's ground
// meets its backdrop at depth.backdrop_m, where a wet ground ending would draw a line across
// the plate's real ground beyond; there the wetness fades out over the guessed ground's far half,
// and the film mirrors nothing: the guess calls ground whatever lies low in the frame (a wall's
// foot, a river), which the mirror of the sky would paint over.
#include <algorithm>
#include <cstring>

#include "optics/drop_shading.h"
#include "rain/wet_ground.h"
#include "stages/clip_plate_rain.h"
#include "stages/depth_grading.h"
#include "stages/depth_settings.h"
#include "stages/lamp_keeping.h"
#include "stages/rain_settings.h"
#include "stages/registry.h"
#include "stages/wet_ground_settings.h"
#include "util/error.h"

namespace pluvia {
namespace {

// The film's gloss: the environment at 64 x 32 (5.6 degree texels, bilinear between them), the
// blur of a rough film rather than a puddle's mirror.
constexpr int kGlossWidth = 64, kGlossHeight = 32;

class WetGroundStage : public Stage {
 public:
  // `guessBackdropMeters`: the guessed depth's backdrop, 0 for a depth that is not a guess.
  WetGroundStage(WetGroundSettings wet, double guessBackdropMeters)
      : wet_(wet), guessBackdropMeters_(guessBackdropMeters) {}

  void prepareAhead(ClipContext& clip) override {
    if (!wet_.overRain) startPlateRainCheck(clip);
  }

  void prepare(ClipContext& clip) override {
    leftOut_ = leaveOutOnRainedPlate(clip, "wet_ground", wet_.overRain);
    if (leftOut_) return;
    findNightPlate(clip);
    if (!clip.environment)
      throw Error("wet_ground needs the lighting stage's environment", {"wet_ground"});
    path_ = clip.cameraPath;
    light_.gloss = resampleEquirect(clip.environment->radiance, kGlossWidth, kGlossHeight);
    light_.irradiance = rain::levelIrradiance(light_.gloss);
  }

  void process(ClipContext& clip, FrameContext& frame) override {
    const std::vector<float>* depth = frame.image.findPlane(kDepthPlane);
    if (leftOut_ || !depth) return;
    const Camera camera = path_.cameraAt(double(frame.frame));
    const std::vector<float>& weights = weightsFor(camera, *depth);
    GradingAov aov(frame.image, "wet_ground");
    const KeptLamps lamps(frame.image, frameLampShare(clip, frame));
    const double gloss = guessBackdropMeters_ > 0.0 ? 0.0 : wet_.gloss;
    rain::wetGround(frame.image, weights, film_, wet_.wetness, gloss, light_, optics::kWaterEta);
    lamps.restore(frame.image);
    aov.finish(frame.image, weights);
  }

 private:
  // The frame's wet weights and what the film shows per pixel, made again only when the depth or
  // the camera changes (a locked-off camera over a static depth makes them once).
  const std::vector<float>& weightsFor(const Camera& camera, const std::vector<float>& depth) {
    const bool same =
        weightsDepth_.size() == depth.size() &&
        std::memcmp(weightsDepth_.data(), depth.data(), depth.size() * sizeof(float)) == 0 &&
        weightsCamera_.positionMeters == camera.positionMeters &&
        weightsCamera_.worldFromCamera == camera.worldFromCamera &&
        weightsCamera_.focalPx == camera.focalPx && weightsCamera_.cx == camera.cx &&
        weightsCamera_.cy == camera.cy;
    if (same) return weights_;
    weights_ = rain::wetGroundWeights(camera, depth, wet_.maxTiltDeg, wet_.fadeDeg);
    if (guessBackdropMeters_ > 0.0)
      for (size_t i = 0; i < weights_.size(); ++i)
        weights_[i] *= float(
            std::clamp(2.0 * (guessBackdropMeters_ - depth[i]) / guessBackdropMeters_, 0.0, 1.0));
    film_ = rain::levelFilmView(camera, weights_, light_, optics::kWaterEta);
    weightsDepth_ = depth;
    weightsCamera_ = camera;
    return weights_;
  }

  WetGroundSettings wet_;
  double guessBackdropMeters_;
  bool leftOut_ = false;
  CameraPath path_;
  rain::WetGroundLight light_;
  std::vector<float> weights_, weightsDepth_;
  rain::LevelFilmView film_;
  Camera weightsCamera_;
};

}  // namespace

StageInfo wetGroundStageInfo() {
  return makeStageInfo(
      wetGroundTable().section(), wetGroundSettings,
      {.noOpReason = [](const WetGroundSettings& wet, const Preset& p) -> std::string {
         if (!rainSettings(p).falls()) return "no rain falls";
         if (wet.wetness == 0.0) return "wetness is 0";
         return "";
       },
       .note = [](const WetGroundSettings& wet,
                  const Preset&) { return rainedPlateNote("wet_ground", wet.overRain); },
       .reads =
           [](const WetGroundSettings& wet, const Preset&) {
             std::vector<std::string> reads{"image", "depth", "environment", "camera"};
             if (!wet.overRain) reads.push_back("plate_rain");
             return reads;
           },
       .cachedWork =
           [](const WetGroundSettings& wet, const Preset&, const ClipInfo& clip,
              const std::string& framesKey, const ArtifactCache& cache) {
             return cachedPlateRainNote(clip, framesKey, cache, wet.overRain);
           },
       .create =
           [](const WetGroundSettings& wet, const Preset& p) {
             const DepthSettings depth = depthSettings(p);
             return std::make_unique<WetGroundStage>(
                 wet, depth.source == DepthSource::Auto ? depth.backdropMeters : 0.0);
           }});
}

}  // namespace pluvia
