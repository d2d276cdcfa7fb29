// Lighting: the environment the drops refract. Until the environment issue stitches panoramas,
// this is a constant radiance or the clip's average colour, held as the order-0 SH coefficient
// (L00 = 2 sqrt(pi) E for a uniform environment of radiance E).
#include <cmath>

#include <fmt/format.h>

#include "pipeline/cache.h"
#include "pluvia/version.h"
#include "stages/registry.h"
#include "util/hash.h"
#include "util/log.h"

namespace pluvia {
namespace {

constexpr const char* kStageVersion = "1";

Environment uniformEnvironment(const std::array<float, 3>& radiance) {
  Environment env;
  env.shOrder = 0;
  const float l00 = float(2.0 * std::sqrt(M_PI));
  env.sh = {{l00 * radiance[0], l00 * radiance[1], l00 * radiance[2]}};
  env.averageRgb = radiance;
  return env;
}

class EnvironmentStage : public Stage {
 public:
  explicit EnvironmentStage(const Preset& p)
      : source_(p.string("lighting.source")),
        color_(p.color("lighting.color")),
        sampleFrames_(int(p.number("lighting.sample_frames"))) {}

  void prepare(ClipContext& clip) override {
    const std::string key = environmentCacheKey(*clip.preset, *clip.clip);
    if (clip.cache) {
      if (auto cached = clip.cache->load("lighting", key)) {
        auto rgb = (*cached)["average_rgb"];
        clip.environment = uniformEnvironment({rgb[0].get<float>(), rgb[1].get<float>(), rgb[2].get<float>()});
        log::info("lighting: from cache");
        return;
      }
    }
    std::array<float, 3> radiance = color_;
    if (source_ == "frame_average") radiance = averageOfFrames(clip);
    clip.environment = uniformEnvironment(radiance);
    log::info(fmt::format("lighting: average radiance {:.4f} {:.4f} {:.4f}", radiance[0], radiance[1], radiance[2]));
    if (clip.cache) clip.cache->store("lighting", key, {{"average_rgb", radiance}});
  }

  static std::string environmentCacheKey(const Preset& p, const ClipInfo& clip) {
    return Hasher()
        .add("lighting")
        .add(kStageVersion)
        .add(kVersion)
        .add(p.at("lighting").dump())
        .add(p.at("color").dump())
        .add(clipIdentity(clip))
        .hex();
  }

 private:
  std::array<float, 3> averageOfFrames(ClipContext& clip) const {
    const auto& frames = clip.clip->frames;
    const int samples = std::max(1, std::min<int>(sampleFrames_, int(frames.size())));
    std::array<double, 3> sum{0, 0, 0};
    for (int s = 0; s < samples; ++s) {
      // Evenly spread over the clip, the first frame included.
      const size_t index = frames.size() * size_t(s) / size_t(samples);
      Image image = clip.readWorking(frames[index]);
      auto mean = meanRgb(image);
      for (int c = 0; c < 3; ++c) sum[c] += mean[c];
    }
    return {float(sum[0] / samples), float(sum[1] / samples), float(sum[2] / samples)};
  }

  std::string source_;
  std::array<float, 3> color_;
  int sampleFrames_;
};

}  // namespace

StageInfo environmentStageInfo() {
  StageInfo info;
  info.spec.name = "lighting";
  info.spec.help = "Environment lighting for the drops (per clip, cached): constant or the clip's average.";
  info.spec.outputs = {"environment"};
  info.spec.params = {
      {"enabled", ParamType::Boolean, true, {}, {}, {}, "", "run this stage"},
      {"source", ParamType::Enum, "frame_average", {}, {}, {"frame_average", "constant"}, "",
       "frame_average: mean radiance of sampled frames; constant: lighting.color"},
      {"color", ParamType::Color3, nlohmann::json::array({0.5, 0.5, 0.5}), {}, {}, {}, "linear",
       "radiance when source is constant"},
      {"sample_frames", ParamType::Integer, 8, 1, 1000, {}, "frames", "frames averaged for frame_average"},
  };
  info.perClip = true;
  info.cacheKey = [](const Preset& p, const ClipInfo& clip) { return EnvironmentStage::environmentCacheKey(p, clip); };
  info.create = [](const Preset& p) { return std::make_unique<EnvironmentStage>(p); };
  return info;
}

}  // namespace pluvia
