// Darken: Starik and Werman's rainy-day look (Wang et al. section 5, "Scene Color"), by depth
// (stages/depth_grading.h): the rain between the camera and the scene greys and darkens what is
// far more than what is near.
#include "image/ops.h"
#include "stages/darken_settings.h"
#include "stages/depth_grading.h"
#include "stages/registry.h"

namespace pluvia {
namespace {

class DarkenStage : public Stage {
 public:
  explicit DarkenStage(DarkenSettings darken) : darken_(darken) {}

  void process(ClipContext&, FrameContext& frame) override {
    const GradingAov aov(frame.image, "darken");
    const std::vector<float> weight = depthGradingWeights(frame.image, darken_.distanceMeters);
    ops::darken(frame.image, float(darken_.amount), float(darken_.darkening), weight.data());
    aov.finish(frame.image, weight);
  }

 private:
  DarkenSettings darken_;
};

}  // namespace

StageInfo darkenStageInfo() {
  return makeStageInfo(
      darkenTable().section(), darkenSettings,
      {.noOpReason = [](const DarkenSettings& darken, const Preset&) -> std::string {
         return darken.amount == 0.0 ? "amount is 0" : "";
       },
       .reads =
           [](const DarkenSettings& darken, const Preset&) {
             return darken.distanceMeters > 0.0 ? std::vector<std::string>{"image", "depth"}
                                                : std::vector<std::string>{"image"};
           },
       .create = [](const DarkenSettings& darken,
                    const Preset&) { return std::make_unique<DarkenStage>(darken); }});
}

}  // namespace pluvia
