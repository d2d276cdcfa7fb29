// Depth: per-frame z-depth in metres for the rain's depth test and the fog. This issue's
// source is manual layers (ground plane from camera height and tilt, cards, sky); "none"
// puts everything at infinity (sky).
#include <limits>

#include "geometry/depth_layers.h"
#include "stages/registry.h"

namespace pluvia {
namespace {

class DepthStage : public Stage {
 public:
  explicit DepthStage(const Preset& p) : source_(p.string("depth.source")), layers_(p.at("depth.layers")) {}

  void prepare(ClipContext& clip) override {
    // Manual layers do not change over frames: rasterise once.
    if (source_ == "layers") {
      depth_ = rasterizeDepthLayers(clip.camera, layers_);
    } else {
      depth_.assign(static_cast<size_t>(clip.camera.width) * clip.camera.height, std::numeric_limits<float>::infinity());
    }
  }
  void process(ClipContext&, FrameContext& frame) override { frame.image.planes["depth"] = depth_; }

 private:
  std::string source_;
  nlohmann::json layers_;
  std::vector<float> depth_;
};

ParamSpec layerField(const std::string& key, double def, double lo, double hi, const std::string& units,
                     const std::string& help) {
  return {key, ParamType::Number, def, lo, hi, {}, units, help};
}

}  // namespace

StageInfo depthStageInfo() {
  StageInfo info;
  info.spec.name = "depth";
  info.spec.help = "Scene depth per frame (metres) from manual layers; sky is at infinity.";
  info.spec.outputs = {"depth"};
  ParamSpec layers{"layers", ParamType::List, nlohmann::json::parse(R"([{"type":"ground"}])"), {}, {}, {}, "",
                   "painted in order, each over the pixels it covers; uncovered pixels are sky"};
  std::vector<ParamSpec> rect{layerField("x0", 0, 0, 1, "", "left edge, fraction of the width"),
                              layerField("x1", 1, 0, 1, "", "right edge, fraction of the width"),
                              layerField("y0", 0, 0, 1, "", "top edge, fraction of the height"),
                              layerField("y1", 1, 0, 1, "", "bottom edge, fraction of the height")};
  std::vector<ParamSpec> card = rect;
  card.push_back(layerField("distance_m", 10, 0.01, 1e6, "m", "z-depth of the card"));
  layers.itemTypes = {{"ground", {}}, {"card", card}, {"sky", rect}};
  info.spec.params = {
      {"enabled", ParamType::Boolean, true, {}, {}, {}, "", "run this stage"},
      {"source", ParamType::Enum, "layers", {}, {}, {"layers", "none"}, "", "where depth comes from"},
      layers,
  };
  info.create = [](const Preset& p) { return std::make_unique<DepthStage>(p); };
  return info;
}

}  // namespace pluvia
