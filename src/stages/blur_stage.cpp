// Blur: the scene seen through rain is softened by refraction in the drops (Wang et al.
// section 5, "Scene Blur"): a Gaussian of sigma pixels.
#include "image/ops.h"
#include "stages/blur_settings.h"
#include "stages/image_op_stage.h"
#include "stages/registry.h"

namespace pluvia {

StageInfo blurStageInfo() {
  StageInfo info;
  info.spec = blurTable().section();
  info.noOpReason = [](const Preset& p) {
    return blurSettings(p).sigmaPx == 0.0 ? std::string("sigma_px is 0") : "";
  };
  info.create = [](const Preset& p) {
    const BlurSettings blur = blurSettings(p);
    return std::make_unique<ImageOpStage>(
        [blur](Image& image) { ops::gaussianBlur(image, float(blur.sigmaPx)); });
  };
  return info;
}

}  // namespace pluvia
