// Blur: the scene seen through rain is softened by refraction in the drops (Wang et al.
// section 5, "Scene Blur"): a Gaussian of sigma pixels.
#include "image/ops.h"
#include "stages/blur_settings.h"
#include "stages/registry.h"

namespace pluvia {
namespace {

class BlurStage : public Stage {
 public:
  explicit BlurStage(BlurSettings blur) : blur_(blur) {}
  void process(ClipContext&, FrameContext& frame) override {
    ops::gaussianBlur(frame.image, float(blur_.sigmaPx));
  }

 private:
  BlurSettings blur_;
};

}  // namespace

StageInfo blurStageInfo() {
  StageInfo info;
  info.spec = blurTable().section();
  info.noOpReason = [](const Preset& p) {
    return blurSettings(p).sigmaPx == 0.0 ? std::string("sigma_px is 0") : "";
  };
  info.create = [](const Preset& p) { return std::make_unique<BlurStage>(blurSettings(p)); };
  return info;
}

}  // namespace pluvia
