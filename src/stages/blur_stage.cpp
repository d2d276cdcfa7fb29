// Blur: the scene seen through rain is softened by the light the drops scatter on its way
// (Wang et al. section 5, "Scene Blur"): a Gaussian of sigma pixels, mixed in by depth
// (stages/depth_grading.h): the scattered share of a ray grows with its path through the rain,
// so the near field stays sharp and the far softens.
#include "image/ops.h"
#include "stages/blur_settings.h"
#include "stages/depth_grading.h"
#include "stages/registry.h"

namespace pluvia {
namespace {

class BlurStage : public Stage {
 public:
  explicit BlurStage(BlurSettings blur) : blur_(blur) {}

  void process(ClipContext&, FrameContext& frame) override {
    const GradingAov aov(frame.image, "blur");
    const std::vector<float> weight = depthGradingWeights(frame.image, blur_.distanceMeters);
    Image blurred;
    blurred.width = frame.image.width;
    blurred.height = frame.image.height;
    blurred.rgba = frame.image.rgba;
    ops::gaussianBlur(blurred, float(blur_.sigmaPx));
    ops::blendToward(frame.image, blurred, weight.data());
    aov.finish(frame.image, weight);
  }

 private:
  BlurSettings blur_;
};

}  // namespace

StageInfo blurStageInfo() {
  return makeStageInfo(blurTable().section(), blurSettings,
                       {.noOpReason = [](const BlurSettings& blur, const Preset&) -> std::string {
                          return blur.sigmaPx == 0.0 ? "sigma_px is 0" : "";
                        },
                        .reads =
                            [](const BlurSettings& blur, const Preset&) {
                              return blur.distanceMeters > 0.0
                                         ? std::vector<std::string>{"image", "depth"}
                                         : std::vector<std::string>{"image"};
                            },
                        .create = [](const BlurSettings& blur,
                                     const Preset&) { return std::make_unique<BlurStage>(blur); }});
}

}  // namespace pluvia
