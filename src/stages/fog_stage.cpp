// Fog: rain too far away to show as streaks reads as fog (Wang et al. section 5, "Rain Fog"):
// alpha = 1 - exp(-density * depth), toward the airlight: the environment's sky at the horizon
// (where a long path through the rain looks, Environment::horizonRgb), or a constant. The sky keeps
// its own colour and detail (it is already the airlight at infinity, image/ops.h), and no path
// through the fog is longer than the visibility through the rain (rain/drop_physics.h).
#include <fmt/format.h>

#include "image/ops.h"
#include "rain/drop_physics.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/log.h"

namespace pluvia {
namespace {

class FogStage : public Stage {
 public:
  explicit FogStage(const Preset& p)
      : preset_(p),
        densityPerMeter_(float(p.number("fog.density"))),
        colorSource_(p.string("fog.color_source")),
        constantRgb_(p.color("fog.color")) {}

  void prepare(ClipContext& clip) override {
    rgb_ = constantRgb_;
    if (colorSource_ == "constant") return;
    if (!clip.environment)
      throw Error("fog takes its colour from the environment, which was not computed", {"fog"});
    rgb_ = colorSource_ == "average" ? clip.environment->averageRgb : clip.environment->horizonRgb;
    log::info(fmt::format("fog: airlight {:.4f} {:.4f} {:.4f} ({})", rgb_[0], rgb_[1], rgb_[2],
                          colorSource_));
  }

  void process(ClipContext&, FrameContext& frame) override {
    // The rain of this frame bounds the path: its visibility (about 2 km at 15 mm/h).
    const bool raining = preset_.boolean("rain.enabled");
    const double visibility =
        raining ? rain::rainVisibilityMeters(preset_.number("rain.rate_mm_h", double(frame.frame)))
                : std::numeric_limits<double>::infinity();
    ops::fog(frame.image, densityPerMeter_, rgb_, float(visibility));
  }

 private:
  const Preset& preset_;
  float densityPerMeter_;
  std::string colorSource_;
  std::array<float, 3> constantRgb_;
  std::array<float, 3> rgb_{0, 0, 0};
};

}  // namespace

StageInfo fogStageInfo() {
  StageInfo info;
  info.spec.name = "fog";
  info.spec.help =
      "Homogeneous fog over the plate by depth: alpha = 1 - exp(-density * depth), toward the "
      "horizon's airlight; the sky keeps its own detail; no path longer than the rain's "
      "visibility.";
  info.spec.inputs = {"image", "depth", "environment"};
  info.spec.outputs = {"image"};
  info.spec.params = {
      {"enabled", ParamType::Boolean, true, {}, {}, {}, "", "run this stage"},
      {"density",
       ParamType::Number,
       0.0,
       0.0,
       10.0,
       {},
       "1/m",
       "extinction per metre; 0 means no fog"},
      {"color_source",
       ParamType::Enum,
       "horizon",
       {},
       {},
       {"horizon", "average", "constant"},
       "",
       "fog colour (airlight): the environment's sky at the horizon, its average over the "
       "sphere, or fog.color"},
      {"color",
       ParamType::Color3,
       nlohmann::json::array({0.5, 0.5, 0.5}),
       {},
       {},
       {},
       "linear",
       "fog colour when color_source is constant"},
  };
  info.noOpReason = [](const Preset& p) {
    return p.number("fog.density") == 0.0 ? std::string("density is 0") : "";
  };
  info.reads = [](const Preset& p) {
    std::vector<std::string> reads{"image", "depth"};
    if (p.string("fog.color_source") != "constant") reads.push_back("environment");
    return reads;
  };
  info.create = [](const Preset& p) { return std::make_unique<FogStage>(p); };
  return info;
}

}  // namespace pluvia
