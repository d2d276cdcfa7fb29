// Fog: rain too far away to show as streaks reads as fog (Wang et al. section 5, "Rain Fog"):
// alpha = 1 - exp(-density * depth), toward the airlight: the environment's sky at the horizon
// (where a long path through the rain looks, Environment::horizonRgb), or a constant. The sky keeps
// its own colour and detail (it is already the airlight at infinity, image/ops.h), and no path
// through the fog is longer than the visibility through the rain (rain/drop_physics.h).
#include <fmt/format.h>

#include "image/ops.h"
#include "rain/drop_physics.h"
#include "stages/fog_settings.h"
#include "stages/rain_settings.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/log.h"

namespace pluvia {
namespace {

class FogStage : public Stage {
 public:
  FogStage(FogSettings fog, RainSettings rain) : fog_(std::move(fog)), rain_(std::move(rain)) {}

  void prepare(ClipContext& clip) override {
    rgb_ = fog_.constantRgb;
    if (fog_.colorSource == "constant") return;
    if (!clip.environment)
      throw Error("fog takes its colour from the environment, which was not computed", {"fog"});
    rgb_ =
        fog_.colorSource == "average" ? clip.environment->averageRgb : clip.environment->horizonRgb;
    log::info(fmt::format("fog: airlight {:.4f} {:.4f} {:.4f} ({})", rgb_[0], rgb_[1], rgb_[2],
                          fog_.colorSource));
  }

  void process(ClipContext&, FrameContext& frame) override {
    // The rain of this frame bounds the path: its visibility (about 2 km at 15 mm/h).
    const double visibility =
        rain_.enabled ? rain::rainVisibilityMeters(rain_.rateMmPerHour.valueAt(double(frame.frame)))
                      : std::numeric_limits<double>::infinity();
    ops::fog(frame.image, float(fog_.densityPerMeter), rgb_, float(visibility));
  }

 private:
  FogSettings fog_;
  RainSettings rain_;
  std::array<float, 3> rgb_{0, 0, 0};
};

}  // namespace

StageInfo fogStageInfo() {
  StageInfo info;
  info.spec = fogSection();
  info.noOpReason = [](const Preset& p) {
    return fogSettings(p).densityPerMeter == 0.0 ? std::string("density is 0") : "";
  };
  info.reads = [](const Preset& p) {
    std::vector<std::string> reads{"image", "depth"};
    if (fogSettings(p).colorSource != "constant") reads.push_back("environment");
    return reads;
  };
  info.create = [](const Preset& p) {
    return std::make_unique<FogStage>(fogSettings(p), rainSettings(p));
  };
  return info;
}

}  // namespace pluvia
