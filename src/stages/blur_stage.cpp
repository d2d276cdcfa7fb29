// Blur: the scene seen through rain is softened by refraction in the drops (Wang et al.
// section 5, "Scene Blur"): a Gaussian of sigma pixels.
#include "image/ops.h"
#include "stages/blur_settings.h"
#include "stages/image_op_stage.h"
#include "stages/registry.h"

namespace pluvia {

StageInfo blurStageInfo() {
  return makeStageInfo(blurTable().section(), blurSettings,
                       {.noOpReason = [](const BlurSettings& blur, const Preset&) -> std::string {
                          return blur.sigmaPx == 0.0 ? "sigma_px is 0" : "";
                        },
                        .create =
                            [](const BlurSettings& blur, const Preset&) {
                              return std::make_unique<ImageOpStage>([blur](Image& image) {
                                ops::gaussianBlur(image, float(blur.sigmaPx));
                              });
                            }});
}

}  // namespace pluvia
