// Lighting: the environment the drops refract, as an equirect radiance map: the shot's own
// frames stitched into a panorama (stitch, Wang et al. section 4.1), an HDR the user gives
// (lighting.hdr), the plate itself (frame, the default: envmap/frame_environment.h), a constant
// radiance, or the clip's average colour in every direction.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "envmap/clip_environment.h"
#include "envmap/frame_environment.h"
#include "optics/environment_file.h"
#include "pipeline/cache.h"
#include "pluvia/version.h"
#include "preset/camera_path_preset.h"
#include "stages/clip_still.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/hash.h"
#include "util/log.h"

namespace pluvia {
namespace {

constexpr const char* kStageVersion = "4";
// A uniform environment needs no detail; an HDR is kept at most this wide (area-resampled, so
// the power of a sun is kept): the drop shading resamples it to 256 x 128 anyway.
constexpr int kUniformWidth = 8;
constexpr int kMaxHdrWidth = 1024;

// The band of elevations whose mean radiance is a map's airlight.
constexpr double kHorizonBandDeg = 10.0;

Environment uniformEnvironment(const std::array<float, 3>& radiance) {
  Environment env;
  env.radiance = uniformEquirect(kUniformWidth, kUniformWidth / 2, radiance);
  env.averageRgb = radiance;
  env.horizonRgb = radiance;
  return env;
}

std::array<float, 3> solidAngleMean(const EquirectMap& map) {
  std::array<double, 3> sum{0, 0, 0};
  double total = 0.0;
  for (int y = 0; y < map.height; ++y) {
    const double w = equirectTexelSolidAngle(map.width, map.height, y);
    for (int x = 0; x < map.width; ++x) {
      for (int c = 0; c < 3; ++c) sum[size_t(c)] += w * map.texel(x, y)[c];
      total += w;
    }
  }
  return {float(sum[0] / total), float(sum[1] / total), float(sum[2] / total)};
}

nlohmann::json equirectJson(const EquirectMap& map) {
  return {{"width", map.width}, {"height", map.height}, {"rgb", map.rgb}};
}

EquirectMap equirectFromJson(const nlohmann::json& json) {
  EquirectMap map(json.at("width").get<int>(), json.at("height").get<int>());
  map.rgb = json.at("rgb").get<std::vector<float>>();
  if (map.rgb.size() != size_t(map.width) * map.height * 3)
    throw Error("cached panorama has the wrong size");
  return map;
}

// The clip's environment from its stitched panoramas (envmap/clip_environment.h): one for a pan
// or a static camera; keys every lighting.every frames for a looming one.
Environment stitchedEnvironment(const nlohmann::json& keys) {
  Environment env;
  for (const auto& key : keys)
    env.keys.emplace_back(key.at("frame").get<int64_t>(), equirectFromJson(key));
  env.radiance = env.keys[env.keys.size() / 2].second;
  env.averageRgb = solidAngleMean(env.radiance);
  env.horizonRgb = equirectBandMean(env.radiance, 0.0, kHorizonBandDeg);
  if (env.keys.size() == 1) env.keys.clear();
  return env;
}

Environment mapEnvironment(EquirectMap map) {
  Environment env;
  env.averageRgb = solidAngleMean(map);
  env.horizonRgb = equirectBandMean(map, 0.0, kHorizonBandDeg);
  env.radiance = std::move(map);
  return env;
}

Environment plateEnvironment(envmap::FrameEnvironment plate) {
  Environment env = mapEnvironment(std::move(plate.radiance));
  env.horizonRgb = plate.horizonRgb;
  return env;
}

nlohmann::json plateJson(const envmap::FrameEnvironment& plate) {
  nlohmann::json json = equirectJson(plate.radiance);
  json["horizon_rgb"] = plate.horizonRgb;
  return json;
}

envmap::FrameEnvironment plateFromJson(const nlohmann::json& json) {
  envmap::FrameEnvironment plate;
  plate.radiance = equirectFromJson(json);
  plate.horizonRgb = json.at("horizon_rgb").get<std::array<float, 3>>();
  return plate;
}

Environment hdrEnvironment(const std::string& path, double intensity) {
  EquirectMap map = optics::loadEnvironment(path);
  if (map.width > kMaxHdrWidth) map = resampleEquirect(map, kMaxHdrWidth, kMaxHdrWidth / 2);
  for (float& v : map.rgb) v *= float(intensity);
  return mapEnvironment(std::move(map));
}

class EnvironmentStage : public Stage {
 public:
  explicit EnvironmentStage(const Preset& p)
      : source_(p.string("lighting.source")),
        color_(p.color("lighting.color")),
        hdr_(p.string("lighting.hdr")),
        intensity_(p.number("lighting.intensity")),
        sampleFrames_(int(p.number("lighting.sample_frames"))) {
    stitch_.horizontalFovDeg = p.number("camera.fov_deg");
    stitch_.motion = p.string("lighting.motion");
    stitch_.every = int(p.number("lighting.every"));
    stitch_.maxPanFrames = int(p.number("lighting.pan_frames"));
    stitch_.inputSpace = p.string("color.input");
    stitch_.lights = envmap::parseLights(p.at("lighting.lights"), "lighting.lights");
  }

  void prepare(ClipContext& clip) override {
    if (source_ == "hdr") {
      if (hdr_.empty())
        throw Error("lighting.source is \"hdr\" but lighting.hdr names no file", {"lighting"});
      clip.environment = hdrEnvironment(hdr_, intensity_);
      const auto& mean = clip.environment->averageRgb;
      log::info(fmt::format("lighting: {} ({} x {}), mean radiance {:.4f} {:.4f} {:.4f}", hdr_,
                            clip.environment->radiance.width, clip.environment->radiance.height,
                            mean[0], mean[1], mean[2]));
      return;
    }
    const std::string key = environmentCacheKey(*clip.preset, *clip.clip);
    if (clip.cache) {
      if (auto cached = clip.cache->load("lighting", key)) {
        if (cached->contains("stitched")) {
          clip.environment = stitchedEnvironment(cached->at("stitched"));
          log::info("lighting: stitched panorama from cache");
          return;
        }
        if (cached->contains("frame")) {
          clip.environment = plateEnvironment(plateFromJson(cached->at("frame")));
          log::info("lighting: from the plate, from cache");
          return;
        }
        auto rgb = (*cached)["average_rgb"];
        clip.environment =
            uniformEnvironment({rgb[0].get<float>(), rgb[1].get<float>(), rgb[2].get<float>()});
        log::info("lighting: from cache");
        return;
      }
    }
    if (source_ == "stitch") {
      nlohmann::json keys = nlohmann::json::array();
      const envmap::ClipEnvironment built =
          envmap::buildClipEnvironment(*clip.reader, clip.clip->frames, stitch_);
      for (const envmap::EnvironmentKey& key : built.keys) {
        nlohmann::json k = equirectJson(key.radiance);
        k["frame"] = key.frame;
        keys.push_back(std::move(k));
      }
      clip.environment = stitchedEnvironment(keys);
      log::info(fmt::format(
          "lighting: stitched ({}, {} panorama{}, {:.0f} % of the sphere seen) in {:.1f} s",
          built.motion, built.keys.size(), built.keys.size() == 1 ? "" : "s",
          100.0 * built.keys.front().coveredFraction, built.seconds));
      if (clip.cache) clip.cache->store("lighting", key, {{"stitched", keys}});
      return;
    }
    if (source_ == "frame") {
      // The camera of the first frame, as the depth stage's guess sees the sky.
      const Camera camera = cameraPathFromPreset(*clip.preset, clip.camera).cameraAt(0.0);
      envmap::FrameEnvironment plate =
          envmap::frameEnvironment(clipStill(clip), camera, clipSky(clip, camera));
      if (clip.cache) clip.cache->store("lighting", key, {{"frame", plateJson(plate)}});
      clip.environment = plateEnvironment(std::move(plate));
      const auto up = equirectBandMean(clip.environment->radiance, 30.0, 90.0);
      const auto down = equirectBandMean(clip.environment->radiance, -90.0, -30.0);
      log::info(
          fmt::format("lighting: from the plate, above {:.4f} {:.4f} {:.4f}, below {:.4f} "
                      "{:.4f} {:.4f}",
                      up[0], up[1], up[2], down[0], down[1], down[2]));
      return;
    }
    std::array<float, 3> radiance = color_;
    if (source_ == "frame_average") radiance = averageOfFrames(clip);
    clip.environment = uniformEnvironment(radiance);
    log::info(fmt::format("lighting: average radiance {:.4f} {:.4f} {:.4f}", radiance[0],
                          radiance[1], radiance[2]));
    if (clip.cache) clip.cache->store("lighting", key, {{"average_rgb", radiance}});
  }

  static std::string environmentCacheKey(const Preset& p, const ClipInfo& clip) {
    // An HDR is read, not computed: nothing to cache (`--require-cache` must not ask for it).
    if (p.string("lighting.source") == "hdr") return std::string();
    return Hasher()
        .add("lighting")
        .add(kStageVersion)
        .add(kVersion)
        .add(p.at("lighting").dump())
        .add(p.at("color").dump())
        .add(p.at("camera").dump())
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
  std::string hdr_;
  double intensity_;
  int sampleFrames_;
  envmap::ClipEnvironmentSettings stitch_;
};

}  // namespace

ParamSpec lightsSpec() {
  auto field = [](const char* key, ParamType type, nlohmann::json value, const char* units,
                  const char* help) {
    return ParamSpec{key, type, std::move(value), -1e9, 1e9, {}, units, help};
  };
  ParamSpec lights{"lights",
                   ParamType::List,
                   nlohmann::json::array(),
                   {},
                   {},
                   {},
                   "",
                   "stitch: light sources the footage saturated, given their measured radiance"};
  const ParamSpec radiance = field("radiance", ParamType::Color3, nlohmann::json::array({1, 1, 1}),
                                   "linear", "measured radiance");
  lights.itemTypes = {
      {"direction",
       {field("yaw_deg", ParamType::Number, 0.0, "deg", "to the right of the first frame's view"),
        field("pitch_deg", ParamType::Number, 45.0, "deg", "above the horizon"),
        field("radius_deg", ParamType::Number, 0.5, "deg", "angular radius"), radiance}},
      {"region",
       {field("frame", ParamType::Integer, 0, "", "index of the frame among those stitched"),
        field("x", ParamType::Integer, 0, "px", "left edge in that frame"),
        field("y", ParamType::Integer, 0, "px", "top edge in that frame"),
        field("width", ParamType::Integer, 1, "px", "width"),
        field("height", ParamType::Integer, 1, "px", "height"), radiance}}};
  return lights;
}

StageInfo environmentStageInfo() {
  StageInfo info;
  info.spec.name = "lighting";
  info.spec.help =
      "Environment lighting for the drops (per clip): an equirect HDR, a constant, or the clip's "
      "average.";
  info.spec.outputs = {"environment"};
  info.spec.params = {
      {"enabled", ParamType::Boolean, true, {}, {}, {}, "", "run this stage"},
      {"source",
       ParamType::Enum,
       "frame",
       {},
       {},
       {"frame", "frame_average", "constant", "hdr", "stitch"},
       "",
       "frame: the plate itself within the camera's view, its mean by elevation elsewhere (the "
       "sky above lights the drops); stitch: the shot's frames stitched into a panorama (Wang et "
       "al. 4.1); frame_average: mean radiance of sampled frames in every direction; constant: "
       "lighting.color; hdr: lighting.hdr"},
      {"motion",
       ParamType::Enum,
       "auto",
       {},
       {},
       {"auto", "pan", "loom", "static"},
       "",
       "stitch: the camera's motion (auto: rotation found by the features makes a pan, a changing "
       "view a loom)"},
      {"every",
       ParamType::Integer,
       5,
       1,
       10000,
       {},
       "frames",
       "stitch, loom: a panorama every N frames"},
      {"pan_frames",
       ParamType::Integer,
       24,
       1,
       500,
       {},
       "frames",
       "stitch, pan: frames stitched, evenly over the clip"},
      lightsSpec(),
      {"hdr",
       ParamType::String,
       "",
       {},
       {},
       {},
       "",
       "equirect HDR (.exr, .hdr; linear Rec.709; +Y up, image centre looking along -Z) for source "
       "hdr"},
      {"intensity",
       ParamType::Number,
       1.0,
       0.0,
       1e6,
       {},
       "",
       "scale on the HDR's radiance, to match the plate"},
      {"color",
       ParamType::Color3,
       nlohmann::json::array({0.5, 0.5, 0.5}),
       {},
       {},
       {},
       "linear",
       "radiance when source is constant"},
      {"sample_frames",
       ParamType::Integer,
       8,
       1,
       1000,
       {},
       "frames",
       "frames averaged for frame_average (frame takes the median of 5 over the clip)"},
  };
  info.perClip = true;
  info.cacheKey = [](const Preset& p, const ClipInfo& clip) {
    return EnvironmentStage::environmentCacheKey(p, clip);
  };
  info.create = [](const Preset& p) { return std::make_unique<EnvironmentStage>(p); };
  return info;
}

}  // namespace pluvia
