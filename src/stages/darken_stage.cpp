// Darken: Starik and Werman's rainy-day look (Wang et al. section 5, "Scene Color").
#include "image/ops.h"
#include "stages/darken_settings.h"
#include "stages/image_op_stage.h"
#include "stages/registry.h"

namespace pluvia {

StageInfo darkenStageInfo() {
  return makeStageInfo(
      darkenTable().section(), darkenSettings,
      {.noOpReason = [](const DarkenSettings& darken, const Preset&) -> std::string {
         return darken.amount == 0.0 ? "amount is 0" : "";
       },
       .create =
           [](const DarkenSettings& darken, const Preset&) {
             return std::make_unique<ImageOpStage>([darken](Image& image) {
               ops::darken(image, float(darken.amount), float(darken.darkening));
             });
           }});
}

}  // namespace pluvia
