// Fog: rain too far away to show as streaks reads as fog (Wang et al. section 5, "Rain Fog"):
// alpha = 1 - exp(-density * depth), coloured by the environment's average radiance or a
// constant.
#include "image/ops.h"
#include "stages/registry.h"
#include "util/error.h"

namespace pluvia {
namespace {

class FogStage : public Stage {
 public:
  explicit FogStage(const Preset& p)
      : densityPerMeter_(float(p.number("fog.density"))),
        useEnvironment_(p.string("fog.color_source") == "environment"),
        constantRgb_(p.color("fog.color")) {}

  void process(ClipContext& clip, FrameContext& frame) override {
    std::array<float, 3> rgb = constantRgb_;
    if (useEnvironment_) {
      if (!clip.environment) throw Error("fog takes its colour from the environment, which was not computed", {"fog", frame.frame});
      rgb = clip.environment->averageRgb;
    }
    ops::fog(frame.image, densityPerMeter_, rgb);
  }

 private:
  float densityPerMeter_;
  bool useEnvironment_;
  std::array<float, 3> constantRgb_;
};

}  // namespace

StageInfo fogStageInfo() {
  StageInfo info;
  info.spec.name = "fog";
  info.spec.help = "Homogeneous fog over the plate by depth: alpha = 1 - exp(-density * depth).";
  info.spec.inputs = {"image", "depth", "environment"};
  info.spec.outputs = {"image"};
  info.spec.params = {
      {"enabled", ParamType::Boolean, true, {}, {}, {}, "", "run this stage"},
      {"density", ParamType::Number, 0.0, 0.0, 10.0, {}, "1/m", "extinction per metre; 0 means no fog"},
      {"color_source", ParamType::Enum, "environment", {}, {}, {"environment", "constant"}, "",
       "fog colour from the environment's average radiance, or fog.color"},
      {"color", ParamType::Color3, nlohmann::json::array({0.5, 0.5, 0.5}), {}, {}, {}, "linear",
       "fog colour when color_source is constant"},
  };
  info.noOpReason = [](const Preset& p) { return p.number("fog.density") == 0.0 ? std::string("density is 0") : ""; };
  info.reads = [](const Preset& p) {
    std::vector<std::string> reads{"image", "depth"};
    if (p.string("fog.color_source") == "environment") reads.push_back("environment");
    return reads;
  };
  info.create = [](const Preset& p) { return std::make_unique<FogStage>(p); };
  return info;
}

}  // namespace pluvia
