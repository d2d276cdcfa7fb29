// Darken: Starik and Werman's rainy-day look (Wang et al. section 5, "Scene Color").
#include "image/ops.h"
#include "stages/registry.h"

namespace pluvia {
namespace {

class DarkenStage : public Stage {
 public:
  explicit DarkenStage(const Preset& p)
      : amount_(float(p.number("darken.amount"))), darkening_(float(p.number("darken.darkening"))) {}
  void process(ClipContext&, FrameContext& frame) override { ops::darken(frame.image, amount_, darkening_); }

 private:
  float amount_, darkening_;
};

}  // namespace

StageInfo darkenStageInfo() {
  StageInfo info;
  info.spec.name = "darken";
  info.spec.help = "Desaturates toward luminance and darkens the plate (Starik–Werman).";
  info.spec.inputs = {"image"};
  info.spec.outputs = {"image"};
  info.spec.params = {
      {"enabled", ParamType::Boolean, true, {}, {}, {}, "", "run this stage"},
      {"amount", ParamType::Number, 0.0, 0.0, 1.0, {}, "", "blend toward luminance; 0 leaves the plate as it is"},
      {"darkening", ParamType::Number, 0.5, 0.0, 1.0, {}, "", "brightness lost at amount 1: out *= 1 - amount*darkening"},
  };
  info.noOpReason = [](const Preset& p) { return p.number("darken.amount") == 0.0 ? std::string("amount is 0") : ""; };
  info.create = [](const Preset& p) { return std::make_unique<DarkenStage>(p); };
  return info;
}

}  // namespace pluvia
