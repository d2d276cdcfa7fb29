// Blur: the scene seen through rain is softened by refraction in the drops (Wang et al.
// section 5, "Scene Blur"): a Gaussian of sigma pixels.
#include "image/ops.h"
#include "stages/registry.h"

namespace pluvia {
namespace {

class BlurStage : public Stage {
 public:
  explicit BlurStage(const Preset& p) : sigmaPx_(float(p.number("blur.sigma_px"))) {}
  void process(ClipContext&, FrameContext& frame) override { ops::gaussianBlur(frame.image, sigmaPx_); }

 private:
  float sigmaPx_;
};

}  // namespace

StageInfo blurStageInfo() {
  StageInfo info;
  info.spec.name = "blur";
  info.spec.help = "Gaussian blur of the plate (refraction through rain).";
  info.spec.inputs = {"image"};
  info.spec.outputs = {"image"};
  info.spec.params = {
      {"enabled", ParamType::Boolean, true, {}, {}, {}, "", "run this stage"},
      {"sigma_px", ParamType::Number, 0.0, 0.0, 100.0, {}, "px", "standard deviation; 0 leaves the plate sharp"},
  };
  info.noOpReason = [](const Preset& p) { return p.number("blur.sigma_px") == 0.0 ? std::string("sigma_px is 0") : ""; };
  info.create = [](const Preset& p) { return std::make_unique<BlurStage>(p); };
  return info;
}

}  // namespace pluvia
