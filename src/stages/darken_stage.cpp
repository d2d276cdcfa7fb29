// Darken: Starik and Werman's rainy-day look (Wang et al. section 5, "Scene Color").
#include "image/ops.h"
#include "stages/darken_settings.h"
#include "stages/registry.h"

namespace pluvia {
namespace {

class DarkenStage : public Stage {
 public:
  explicit DarkenStage(DarkenSettings darken) : darken_(darken) {}
  void process(ClipContext&, FrameContext& frame) override {
    ops::darken(frame.image, float(darken_.amount), float(darken_.darkening));
  }

 private:
  DarkenSettings darken_;
};

}  // namespace

StageInfo darkenStageInfo() {
  StageInfo info;
  info.spec = darkenTable().section();
  info.noOpReason = [](const Preset& p) {
    return darkenSettings(p).amount == 0.0 ? std::string("amount is 0") : "";
  };
  info.create = [](const Preset& p) { return std::make_unique<DarkenStage>(darkenSettings(p)); };
  return info;
}

}  // namespace pluvia
