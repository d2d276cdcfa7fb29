// Darken: Starik and Werman's rainy-day look (Wang et al. section 5, "Scene Color").
#include "image/ops.h"
#include "stages/darken_settings.h"
#include "stages/image_op_stage.h"
#include "stages/registry.h"

namespace pluvia {

StageInfo darkenStageInfo() {
  StageInfo info;
  info.spec = darkenTable().section();
  info.noOpReason = [](const Preset& p) {
    return darkenSettings(p).amount == 0.0 ? std::string("amount is 0") : "";
  };
  info.create = [](const Preset& p) {
    const DarkenSettings darken = darkenSettings(p);
    return std::make_unique<ImageOpStage>([darken](Image& image) {
      ops::darken(image, float(darken.amount), float(darken.darkening));
    });
  };
  return info;
}

}  // namespace pluvia
