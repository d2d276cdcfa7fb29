// Ripples: where the rain's drops strike level ground, the rings of rain/ripples.h, drawn before
// the rain falls in front of them (rain/ripple_field.h): the impacts are the splash stage's
// kind (rain/splashes.h, impactsBorn: deterministic per birth frame and tile), those still
// ringing at the frame's shutter midpoint; the water mirrors the plate's own reflection displaced
// by the rings, and the lighting stage's environment where the plate does not show it.
#include <cmath>

#include "image/equirect.h"
#include "rain/ripple_field.h"
#include "rain/splash_memo.h"
#include "rain/splash_rate.h"
#include "stages/depth_grading.h"
#include "stages/rain_settings.h"
#include "stages/registry.h"
#include "stages/ripples_settings.h"
#include "util/error.h"

namespace pluvia {
namespace {

constexpr double kMaxDiameterMm = 6.0;          // drops break up above (rain/drop_simulation.h)
constexpr uint64_t kRippleSalt = 0x51bb1e5ULL;  // the rings' impacts apart from the splashes'

class RipplesStage : public Stage {
 public:
  RipplesStage(RipplesSettings ripples, RainSettings rain)
      : ripples_(ripples), rain_(std::move(rain)) {}

  void prepare(ClipContext& clip) override {
    if (!clip.environment)
      throw Error("ripples need the lighting stage's environment", {"ripples"});
    path_ = clip.cameraPath;
    fps_ = clip.fps;
    environment_ = clip.environment->radiance;
  }

  void process(ClipContext&, FrameContext& frame) override {
    const std::vector<float>* depth = frame.image.findPlane(kDepthPlane);
    const double f = double(frame.frame);
    const double rate = rain_.rateMmPerHour.valueAt(f);
    if (!depth || rate <= 0.0) return;
    const Camera camera = path_.cameraAt(f);
    rain::SplashFieldInputs inputs;
    inputs.maxTiltDeg = ripples_.maxTiltDeg;
    inputs.maxDepthMeters = rain::rippleReachMeters(camera);
    inputs.impactsPerSquareMeterSecond = rain::impactsPerSquareMeterSecond(
        rain_.distribution, rain_.velocity, rate, ripples_.minDiameterMm, kMaxDiameterMm);
    // A rate whose flux underflows to 0 (1e-308 mm/h) lands no drop: nothing to draw.
    if (!(inputs.impactsPerSquareMeterSecond > 0.0)) return;
    memo_.setField(camera, *depth, inputs);
    const rain::SplashField& field = memo_.field();
    std::vector<uint8_t> water(field.areaPerPixel.size());
    bool any = false;
    for (size_t i = 0; i < water.size(); ++i) any |= (water[i] = field.areaPerPixel[i] > 0.0f);
    if (!any) return;
    const rain::ImpactDiameters diameters(rain_.distribution, rain_.velocity, rate,
                                          ripples_.minDiameterMm, kMaxDiameterMm);
    const double now = (f + 0.5) / fps_;
    const double longest = rain::rippleLifeSeconds(
        {{}, 0.0, kMaxDiameterMm, rain::terminalVelocity(rain_.velocity, kMaxDiameterMm), 0});
    const int64_t firstBirth = frame.frame - int64_t(std::ceil(longest * fps_));
    std::vector<const rain::Impact*> alive;
    for (const std::vector<rain::Impact>* some :
         memo_.impacts(firstBirth, frame.frame, fps_, rain_.seed ^ kRippleSalt, diameters, rate,
                       rain_.velocity))
      for (const rain::Impact& impact : *some)
        if (impact.timeSeconds <= now && impact.timeSeconds + rain::rippleLifeSeconds(impact) > now)
          alive.push_back(&impact);
    GradingAov aov(frame.image, "ripples");
    std::vector<float> slopeX(water.size(), 0.0f), slopeZ(water.size(), 0.0f);
    rain::addRippleSlopes(camera, *depth, water, alive, now, slopeX, slopeZ);
    // The plate before the rings, for the water to mirror its own reflection displaced.
    Image plate;
    plate.width = frame.image.width;
    plate.height = frame.image.height;
    plate.rgba = frame.image.rgba;
    rain::shadeRippleMirror(
        frame.image, camera, *depth, slopeX, slopeZ,
        [&](const Eigen::Vector3d& d) {
          return sampleEquirect(environment_, float(d.x()), float(d.y()), float(d.z()));
        },
        &plate, &water);
    aov.finish(frame.image, {});
  }

 private:
  RipplesSettings ripples_;
  RainSettings rain_;
  CameraPath path_;
  double fps_ = 24.0;
  EquirectMap environment_;
  rain::SplashMemo memo_;
};

}  // namespace

StageInfo ripplesStageInfo() {
  return makeStageInfo(
      ripplesTable().section(), ripplesSettings,
      {.noOpReason = [](const RipplesSettings&, const Preset& p) -> std::string {
         if (!rainSettings(p).falls()) return "no rain falls";
         return "";
       },
       .reads =
           [](const RipplesSettings&, const Preset&) {
             return std::vector<std::string>{"image", "depth", "environment", "camera"};
           },
       .create =
           [](const RipplesSettings& ripples, const Preset& p) {
             return std::make_unique<RipplesStage>(ripples, rainSettings(p));
           }});
}

}  // namespace pluvia
