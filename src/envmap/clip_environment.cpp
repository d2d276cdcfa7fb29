#include "envmap/clip_environment.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "image/color.h"
#include "util/error.h"
#include "util/log.h"
#include "util/median.h"
#include "util/timer.h"

namespace pluvia::envmap {

const char* motionName(StitchMotion motion) {
  for (const auto& [name, value] : kStitchMotionNames)
    if (value == motion) return name;
  return "auto";
}

std::optional<StitchMotion> stitchMotionNamed(const std::string& name) {
  for (const auto& [known, value] : kStitchMotionNames)
    if (name == known) return value;
  return std::nullopt;
}
namespace {

// A source pixel at or above this in the file's 0..1 encoding counts as clipped.
constexpr float kSaturatedLevel = 254.5f / 255.0f;
// Frames whose median absolute difference stays below this (linear 0..1) show a static camera:
// the median ignores people and cars moving through a locked-off shot.
constexpr double kStaticDifference = 0.01;

struct FrameReader {
  ClipReader& reader;
  ColorConverter toLinear;

  PanoramaFrame read(int64_t frame) {
    Image image = reader.read(frame);
    PanoramaFrame out;
    out.saturated = cv::Mat::zeros(image.height, image.width, CV_8U);
    if (!reader.info().isFloat) {
      for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
          const float* p = image.pixel(x, y);
          if (p[0] >= kSaturatedLevel || p[1] >= kSaturatedLevel || p[2] >= kSaturatedLevel)
            out.saturated.at<uint8_t>(y, x) = 255;
        }
    }
    toLinear.apply(image);
    out.linearRgb = rgbMat(image);
    return out;
  }
};

std::vector<int64_t> evenly(const std::vector<int64_t>& frames, int count) {
  if (int(frames.size()) <= count) return frames;
  std::vector<int64_t> picked;
  for (int i = 0; i < count; ++i)
    picked.push_back(frames[size_t(i) * (frames.size() - 1) / size_t(count - 1)]);
  return picked;
}

// Widest angle between any frame's viewing direction and frame 0's, degrees.
double rotationSpanDeg(const Placement& placement) {
  double span = 0.0;
  for (const CameraPose& pose : placement.poses) {
    const cv::Vec3d forward = pose.cameraToWorld * cv::Vec3d(0, 0, -1);
    span = std::max(span, std::acos(std::clamp(-forward[2], -1.0, 1.0)) * 180.0 / M_PI);
  }
  return span;
}

EnvironmentKey makeKey(int64_t frame, const std::vector<PanoramaFrame>& frames,
                       const Placement& placement, const ClipEnvironmentSettings& settings) {
  EquirectSettings render;
  render.width = settings.width;
  render.lights = settings.lights;
  render.fill = settings.fill;
  const PanoramaResult panorama = renderEquirect(frames, placement, render);
  EnvironmentKey key;
  key.frame = frame;
  key.radiance = panorama.radiance;
  key.sh = optics::projectEnvironment(key.radiance, settings.shOrder);
  key.coveredFraction = panorama.coveredFraction;
  key.fromFeatures = placement.fromFeatures;
  return key;
}

double medianAbsDifference(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat difference = cv::abs(a - b);
  std::vector<float> values(difference.begin<float>(), difference.end<float>());
  if (values.empty()) return 0.0;
  return medianInPlace(values.data(), values.size());
}

}  // namespace

ClipEnvironment buildClipEnvironment(ClipReader& reader, const std::vector<int64_t>& frames,
                                     const ClipEnvironmentSettings& settings) {
  const auto started = std::chrono::steady_clock::now();
  if (frames.empty())
    throw Error("no frames to build an environment from", {"lighting", {}, reader.info().path});
  const std::string space = settings.inputSpace == "auto"
                                ? (reader.info().isFloat ? "linear-rec709" : "sRGB")
                                : settings.inputSpace;
  FrameReader frameReader{reader, ColorConverter(space, "linear-rec709")};
  PlacementSettings placementSettings;
  placementSettings.horizontalFovDeg = settings.horizontalFovDeg;

  ClipEnvironment env;
  StitchMotion motion = settings.motion;
  std::vector<PanoramaFrame> panFrames;
  std::vector<int64_t> panNumbers;
  Placement panPlacement;
  if (motion == StitchMotion::Auto || motion == StitchMotion::Pan) {
    panNumbers = evenly(frames, settings.maxPanFrames);
    for (int64_t f : panNumbers) panFrames.push_back(frameReader.read(f));
    panPlacement = placeFrames(panFrames, placementSettings);
    if (motion == StitchMotion::Auto) {
      const bool rotates = panPlacement.fromFeatures &&
                           rotationSpanDeg(panPlacement) > settings.horizontalFovDeg / 4;
      const bool changes =
          panFrames.size() > 1 &&
          medianAbsDifference(panFrames.front().linearRgb.reshape(1),
                              panFrames.back().linearRgb.reshape(1)) > kStaticDifference;
      motion = rotates                                          ? StitchMotion::Pan
               : changes && int(frames.size()) > settings.every ? StitchMotion::Loom
                                                                : StitchMotion::Static;
    }
    if (panPlacement.fromFeatures && !panPlacement.interpolated.empty()) {
      std::vector<int64_t> numbers;
      for (int k : panPlacement.interpolated) numbers.push_back(panNumbers[size_t(k)]);
      log::info(
          fmt::format("lighting: frames {} have too few features to match: placed between "
                      "their neighbours; the others by their features",
                      fmt::join(numbers, ", ")));
    }
    if (!panPlacement.fromFeatures && panFrames.size() > 1) {
      env.warnings.push_back(panPlacement.note +
                             (motion == StitchMotion::Pan
                                  ? "; frames placed by the field of view"
                                  : std::string("; taken as a ") + motionName(motion) + " camera"));
    }
  }
  env.motion = motionName(motion);
  if (motion == StitchMotion::Pan) {
    env.keys.push_back(
        makeKey(panNumbers[panNumbers.size() / 2], panFrames, panPlacement, settings));
  } else if (motion == StitchMotion::Static) {
    const std::vector<PanoramaFrame> one = {frameReader.read(frames.front())};
    env.keys.push_back(makeKey(frames.front(), one, placeFrames(one, placementSettings), settings));
  } else {
    // loom: a view-dependent environment every `every` frames. A looming camera does not turn,
    // so the frames between keys add no new directions: each key is its frame's view.
    for (size_t i = 0; i < frames.size(); i += size_t(settings.every)) {
      const std::vector<PanoramaFrame> one = {frameReader.read(frames[i])};
      env.keys.push_back(makeKey(frames[i], one, placeFrames(one, placementSettings), settings));
    }
  }
  for (const std::string& w : env.warnings) log::warning("lighting: " + w);
  env.seconds = secondsSince(started);
  return env;
}

std::vector<LightSource> parseLights(const nlohmann::json& lights, const std::string& source) {
  std::vector<LightSource> out;
  if (!lights.is_array()) throw Error("lights must be a list", {"lighting", {}, source});
  for (size_t i = 0; i < lights.size(); ++i) {
    const nlohmann::json& item = lights[i];
    try {
      LightSource light;
      const auto radiance = item.at("radiance").get<std::array<float, 3>>();
      for (float v : radiance)
        if (!std::isfinite(v) || v < 0) throw Error("radiance must be finite and not negative");
      light.radiance = radiance;
      const std::string type = item.at("type").get<std::string>();
      if (type == "direction") {
        const double yaw = item.at("yaw_deg").get<double>() * M_PI / 180.0;
        const double pitch = item.at("pitch_deg").get<double>() * M_PI / 180.0;
        light.direction = std::array<double, 3>{std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                                                -std::cos(yaw) * std::cos(pitch)};
        light.radiusDeg = item.value("radius_deg", 0.5);
        if (!(light.radiusDeg > 0)) throw Error("radius_deg must be positive");
      } else if (type == "region") {
        light.frame = item.at("frame").get<int>();
        light.region = cv::Rect(item.at("x").get<int>(), item.at("y").get<int>(),
                                item.at("width").get<int>(), item.at("height").get<int>());
        if (light.frame < 0 || light.region.width <= 0 || light.region.height <= 0)
          throw Error("frame must be >= 0, width and height positive");
      } else {
        throw Error(fmt::format("unknown light type '{}' (direction, region)", type));
      }
      out.push_back(light);
    } catch (const nlohmann::json::exception& e) {
      throw Error(fmt::format("light {}: {}", i, e.what()), {"lighting", {}, source});
    } catch (const Error& e) {
      throw Error(fmt::format("light {}: {}", i, e.what()), {"lighting", {}, source});
    }
  }
  return out;
}

nlohmann::json clipEnvironmentJson(const ClipEnvironment& environment,
                                   const std::vector<int64_t>& frames) {
  nlohmann::json keys = nlohmann::json::array(), perFrame = nlohmann::json::array();
  for (const EnvironmentKey& key : environment.keys)
    keys.push_back({{"frame", key.frame},
                    {"covered_fraction", key.coveredFraction},
                    {"from_features", key.fromFeatures},
                    {"sh", key.sh}});
  for (int64_t f : frames) perFrame.push_back({{"frame", f}, {"sh", shAtFrame(environment, f)}});
  const size_t coefficients = environment.keys.front().sh.size();
  return {{"pluvia_envmap", 1},
          {"motion", environment.motion},
          {"sh_order", int(std::lround(std::sqrt(double(coefficients)))) - 1},
          {"keys", keys},
          {"frames", perFrame},
          {"warnings", environment.warnings},
          {"seconds", environment.seconds}};
}

optics::ShCoefficients shAtFrame(const ClipEnvironment& environment, int64_t frame) {
  const auto& keys = environment.keys;
  if (keys.empty()) return {};
  if (frame <= keys.front().frame) return keys.front().sh;
  if (frame >= keys.back().frame) return keys.back().sh;
  size_t next = 1;
  while (keys[next].frame < frame) ++next;
  const EnvironmentKey& a = keys[next - 1];
  const EnvironmentKey& b = keys[next];
  const double t = double(frame - a.frame) / double(b.frame - a.frame);
  optics::ShCoefficients sh = a.sh;
  for (size_t i = 0; i < sh.size(); ++i)
    for (int c = 0; c < 3; ++c)
      sh[i][size_t(c)] = (1.0 - t) * a.sh[i][size_t(c)] + t * b.sh[i][size_t(c)];
  return sh;
}

}  // namespace pluvia::envmap
