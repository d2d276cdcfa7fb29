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
#include "pipeline/camera_settings.h"
#include "pipeline/color_settings.h"
#include "pipeline/plate_lens.h"
#include "pluvia/version.h"
#include "stages/clip_still.h"
#include "stages/lighting_settings.h"
#include "stages/plate_lights.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/hash.h"
#include "util/log.h"

namespace pluvia {
namespace {

constexpr const char* kStageVersion = "7";  // 7: a clear sky as the plate shows it
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

// A cache entry is a file anyone can edit: its sizes are checked against the samples it holds
// before anything is allocated.
EquirectMap equirectFromJson(const nlohmann::json& json) {
  const int width = json.at("width").get<int>(), height = json.at("height").get<int>();
  const nlohmann::json& rgb = json.at("rgb");
  if (width < 1 || height < 1 || width > 65536 || height > 65536 || !rgb.is_array() ||
      rgb.size() != size_t(width) * size_t(height) * 3)
    throw Error(fmt::format("cached panorama: {}x{} does not match its {} samples", width, height,
                            rgb.is_array() ? rgb.size() : 0));
  EquirectMap map(width, height);
  map.rgb = rgb.get<std::vector<float>>();
  return map;
}

// The clip's environment from its stitched panoramas (envmap/clip_environment.h): one for a pan
// or a static camera; keys every lighting.every frames for a looming one.
Environment stitchedEnvironment(const nlohmann::json& keys) {
  if (!keys.is_array() || keys.empty()) throw Error("cached stitch: no panorama");
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

// The environment a cache entry holds (as prepare() stores it); throws on a malformed entry.
Environment cachedEnvironment(const nlohmann::json& cached) {
  if (cached.contains("stitched")) {
    Environment env = stitchedEnvironment(cached.at("stitched"));
    log::info("lighting: stitched panorama from cache");
    return env;
  }
  if (cached.contains("frame")) {
    Environment env = plateEnvironment(plateFromJson(cached.at("frame")));
    log::info("lighting: from the plate, from cache");
    return env;
  }
  const nlohmann::json& rgb = cached.at("average_rgb");
  Environment env =
      uniformEnvironment({rgb.at(0).get<float>(), rgb.at(1).get<float>(), rgb.at(2).get<float>()});
  log::info("lighting: from cache");
  return env;
}

// A cache entry is a file anyone can edit (or a crash may have cut): one that does not read as
// the lighting pluvia stored is measured again, and stored anew.
void ignoreMalformedEntry(const ClipContext& clip, const std::string& key, const std::string& why) {
  log::warning(fmt::format("ignoring the malformed cache entry {} ({}): measuring again",
                           clip.cache->pathFor("lighting", key).string(), why));
}

// What of the camera the environment is made with: where it looks (the stitch's field of view,
// the first frame's pose), not how it exposes or focuses, so that a --set of the shutter or
// the lens's aperture finds the environment in the cache.
nlohmann::json lightingCamera(const CameraSettings& camera) {
  nlohmann::json used;
  // lens_from_plate: whether the plate's stated view replaces fov_deg in the stitch.
  for (const char* key : {"fov_deg", "lens_from_plate", "tilt_deg", "height_m", "path"})
    if (camera.resolved.contains(key)) used[key] = camera.resolved.at(key);
  return used;
}

// What the environment depends on: the lighting, the colour spaces, the camera and the clip.
std::string environmentCacheKey(const LightingSettings& lighting, const ColorSettings& color,
                                const CameraSettings& camera, const ClipInfo& clip) {
  return Hasher()
      .add("lighting")
      .add(kStageVersion)
      .add(kVersion)
      .add(lighting.resolved.dump())
      .add(color.resolved.dump())
      .add(lightingCamera(camera).dump())
      .add(clipIdentity(clip))
      .hex();
}

class EnvironmentStage : public Stage {
 public:
  EnvironmentStage(LightingSettings lighting, ColorSettings color, CameraSettings camera)
      : lighting_(std::move(lighting)), color_(std::move(color)), camera_(std::move(camera)) {
    stitch_.motion = lighting_.motion;
    stitch_.every = lighting_.everyFrames;
    stitch_.maxPanFrames = lighting_.panFrames;
    stitch_.fill = lighting_.unseenFill;
    stitch_.inputSpace = color_.inputSpace;
    stitch_.lights = envmap::parseLights(lighting_.lights, "lighting.lights");
  }

  void prepare(ClipContext& clip) override {
    stitch_.horizontalFovDeg = withPlateLens(camera_, clip.plateLens).fovDeg;
    const LightingSource source = lighting_.source;
    if (source == LightingSource::Hdr) {
      const std::string& hdr = lighting_.hdrPath;  // never empty here (lightingSettings)
      clip.environment = hdrEnvironment(hdr, lighting_.intensity);
      const auto& mean = clip.environment->averageRgb;
      log::info(fmt::format("lighting: {} ({} x {}), mean radiance {:.4f} {:.4f} {:.4f}", hdr,
                            clip.environment->radiance.width, clip.environment->radiance.height,
                            mean[0], mean[1], mean[2]));
      return;
    }
    const std::string key = environmentCacheKey(lighting_, color_, camera_, *clip.clip);
    if (clip.cache) {
      if (auto cached = clip.cache->load("lighting", key)) {
        try {
          clip.environment = cachedEnvironment(*cached);
          return;
        } catch (const nlohmann::json::exception&) {
          ignoreMalformedEntry(clip, key, "a field is missing or of the wrong type");
        } catch (const Error& e) {
          ignoreMalformedEntry(clip, key, e.what());
        } catch (const std::bad_alloc&) {
          ignoreMalformedEntry(clip, key, "its sizes are beyond memory");
        }
      }
    }
    if (source == LightingSource::Stitch) {
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
    if (source == LightingSource::Frame) {
      // The camera of the first frame, as the depth stage's guess sees the sky.
      const Camera camera = camera_.path(clip.camera).cameraAt(0.0);
      const Image& still = clipStill(clip);
      const bool night = isNightPlate(plateLuminance(still));
      envmap::FrameEnvironment plate =
          envmap::frameEnvironment(still, camera, clipSky(clip, camera), night);
      log::info(
          fmt::format("lighting: the sky above the plate has a zenith luminance of {:.3f} ({})",
                      plate.zenithLuminance,
                      night ? "a night plate: only the sky it shows, its lamps light the rest"
                      : plate.clearSky ? "a clear sky: the plate's own, as it shows it; rain is "
                                         "faint under it, its sun's glints not drawn"
                      : plate.skyFromPlate
                          ? "through the plate's own sky"
                          : "the sky that lights the scene as brightly as the plate shows it"));
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
    std::array<float, 3> radiance = lighting_.constantRgb;
    if (source == LightingSource::FrameAverage) radiance = averageOfFrames(clip);
    clip.environment = uniformEnvironment(radiance);
    log::info(fmt::format("lighting: average radiance {:.4f} {:.4f} {:.4f}", radiance[0],
                          radiance[1], radiance[2]));
    if (clip.cache) clip.cache->store("lighting", key, {{"average_rgb", radiance}});
  }

 private:
  std::array<float, 3> averageOfFrames(ClipContext& clip) const {
    const auto& frames = clip.clip->frames;
    const int samples = std::max(1, std::min<int>(lighting_.sampleFrames, int(frames.size())));
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

  LightingSettings lighting_;
  ColorSettings color_;
  CameraSettings camera_;
  envmap::ClipEnvironmentSettings stitch_;
};

}  // namespace

StageInfo lightingStageInfo() {
  return makeStageInfo(
      lightingTable().section(), lightingSettings,
      {.perClip = true,
       // Which sky the drops are lit by, before the analysis says how bright (the log does).
       .note = [](const LightingSettings& lighting, const Preset&) -> std::string {
         if (lighting.source != LightingSource::Frame) return "";
         return "drops lit by the plate and, above it, an overcast sky (zenith 3x the horizon): "
                "the brighter of the plate's own sky and the sky that lights its scene as "
                "brightly as the plate shows it (about 34x its mean luminance), the plate's own "
                "sky lifted onto it where it clips, and below the frame wet ground mirroring "
                "it; a clear (blue) sky in the plate is taken as it shows it, and the rain under "
                "it is faint (its sun's glints are not drawn); a night plate keeps only the sky it "
                "shows";
       },
       .reads =
           [](const LightingSettings& lighting, const Preset&) {
             return lighting.source == LightingSource::Frame ? std::vector<std::string>{"still"}
                                                             : std::vector<std::string>{};
           },
       .cacheKey =
           [](const LightingSettings& lighting, const Preset& p, const ClipInfo& clip) {
             // An HDR is read, not computed: nothing to cache (`--require-cache` must not ask
             // for it).
             if (lighting.source == LightingSource::Hdr) return std::string();
             return environmentCacheKey(lighting, colorSettings(p), cameraSettings(p), clip);
           },
       .create =
           [](const LightingSettings& lighting, const Preset& p) {
             return std::make_unique<EnvironmentStage>(lighting, colorSettings(p),
                                                       cameraSettings(p));
           }});
}

}  // namespace pluvia
