#include "stages/clip_plate_rain.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <optional>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "derain/plate_rain.h"
#include "image/srgb.h"
#include "pipeline/cache.h"
#include "pluvia/version.h"
#include "util/hash.h"
#include "util/log.h"
#include "util/thread_limit.h"
#include "util/timer.h"

namespace pluvia {
namespace {

constexpr size_t kFramesRead = 9;     // the 3 measured and 3 neighbours either side
constexpr int kMeasureWidthPx = 640;  // the width real rain's thresholds are set at

// A working-space frame as the BGR display codes the measurement takes, kMeasureWidthPx wide.
cv::Mat3f displayCodes(const Image& image) {
  cv::Mat rgba(image.height, image.width, CV_32FC4, const_cast<float*>(image.rgba.data()));
  cv::Mat bgr, small;
  cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
  const int width = std::min(kMeasureWidthPx, image.width);
  const int height = std::max(1, int(std::lround(double(image.height) * width / image.width)));
  cv::resize(bgr, small, cv::Size(width, height), 0, 0, cv::INTER_AREA);
  cv::Mat3f codes(small);
  for (cv::Vec3f& p : cv::Mat_<cv::Vec3f>(codes))
    for (int c = 0; c < 3; ++c) p[c] = float(255.0 * srgbEncode(std::clamp(p[c], 0.0f, 1.0f)));
  return codes;
}

// The finding's cache entry: the frames it is measured on. "" (not cached) without them.
std::string plateRainKey(const std::string& framesKey) {
  if (framesKey.empty()) return "";
  return Hasher()
      .add("plate-rain")
      .add(kVersion)
      .add(framesKey)
      .add(uint64_t(kFramesRead))
      .add(uint64_t(kMeasureWidthPx))
      .hex();
}

// Measured on `read`'s frames: 9 consecutive ones from the clip's middle.
PlateRainFinding measureOn(const ClipInfo& clip, const std::function<Image(int64_t)>& read) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<int64_t>& frames = clip.frames;
  const size_t count = std::min(frames.size(), kFramesRead);
  const size_t first = (frames.size() - count) / 2;
  std::vector<cv::Mat3f> codes;
  for (size_t i = first; i < first + count; ++i) codes.push_back(displayCodes(read(frames[i])));
  const derain::PlateRain rain = derain::measurePlateRain(codes);
  // No streaks leave the medians NaN (which JSON cannot hold): 0, none.
  const auto finiteOr0 = [](double v) { return std::isfinite(v) ? v : 0.0; };
  return {rain.rained,
          finiteOr0(rain.stats.lengthP50Px),
          finiteOr0(rain.stats.widthP50Px),
          finiteOr0(rain.stats.elongationByLightP50),
          rain.summary(),
          secondsSince(start)};
}

bool measurable(const ClipContext& clip) {
  return clip.clip && clip.readWorking && clip.clip->frames.size() >= 3;
}

// The cached finding, when the cache holds one for the clip's frames.
std::optional<PlateRainFinding> cachedFinding(const ClipContext& clip) {
  const std::string key = plateRainKey(clip.framesKey);
  if (!clip.cache || key.empty()) return std::nullopt;
  auto cached = clip.cache->load("plate-rain", key);
  if (!cached) return std::nullopt;
  try {
    PlateRainFinding finding;
    finding.rained = cached->at("rained").get<bool>();
    finding.summary = cached->at("summary").get<std::string>();
    finding.streakLengthPx = cached->at("streak_length_px").get<double>();
    finding.streakWidthPx = cached->at("streak_width_px").get<double>();
    finding.streakElongationByLight = cached->at("streak_elongation_by_light").get<double>();
    log::info(fmt::format("plate: {} in rain: {}, from cache", finding.rained ? "shot" : "not shot",
                          finding.summary));
    return finding;
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;  // malformed: measured again and stored over it
  }
}

const PlateRainFinding& keepMeasured(ClipContext& clip, const PlateRainFinding& finding) {
  log::info(fmt::format("plate: {} in rain: {}, in {:.1f} s", finding.rained ? "shot" : "not shot",
                        finding.summary, finding.measuredSeconds));
  const std::string key = plateRainKey(clip.framesKey);
  if (clip.cache && !key.empty())
    clip.cache->store("plate-rain", key,
                      {{"rained", finding.rained},
                       {"streak_length_px", finding.streakLengthPx},
                       {"streak_width_px", finding.streakWidthPx},
                       {"streak_elongation_by_light", finding.streakElongationByLight},
                       {"summary", finding.summary}});
  return clip.plateRain.emplace(finding);
}

}  // namespace

void startPlateRainCheck(ClipContext& clip) {
  if (clip.plateRain || clip.plateRainAhead.valid() || !measurable(clip) ||
      !clip.openWorkingReader || threadLimit() < 2)
    return;
  if (std::optional<PlateRainFinding> cached = cachedFinding(clip)) {
    clip.plateRain.emplace(*cached);
    return;
  }
  clip.plateRainAhead =
      std::async(std::launch::async,
                 [info = clip.clip,
                  open = clip.openFilmedReader ? clip.openFilmedReader : clip.openWorkingReader] {
                   return measureOn(*info, open());
                 });
}

const PlateRainFinding& clipPlateRain(ClipContext& clip) {
  if (clip.plateRain) return *clip.plateRain;
  if (clip.plateRainAhead.valid()) return keepMeasured(clip, clip.plateRainAhead.get());
  if (!measurable(clip)) {
    PlateRainFinding finding;
    finding.summary = "fewer than 3 frames to measure: taken as dry";
    return clip.plateRain.emplace(finding);
  }
  if (std::optional<PlateRainFinding> cached = cachedFinding(clip))
    return clip.plateRain.emplace(*cached);
  // A proxy's at the size it was filmed at: the thresholds are real rain's at 640 px.
  return keepMeasured(clip, measureOn(*clip.clip, clip.openFilmedReader ? clip.openFilmedReader()
                                                                        : clip.readWorking));
}

bool leaveOutOnRainedPlate(ClipContext& clip, const std::string& stage, bool overRain) {
  if (overRain || !clipPlateRain(clip).rained) return false;
  log::info(fmt::format(
      "{0}: left out: the plate was shot in rain and already shows what it adds; {0}.over_rain = "
      "true adds it anyway",
      stage));
  return true;
}

std::string rainedPlateNote(const std::string& stage, bool overRain) {
  return overRain ? fmt::format("also on a plate shot in rain ({}.over_rain)", stage)
                  : fmt::format(
                        "left out at render time on a plate shot in rain (its own "
                        "streaks; {}.over_rain = true adds it anyway)",
                        stage);
}

std::string cachedPlateRainNote(const ClipInfo& clip, const std::string& framesKey,
                                const ArtifactCache& cache, bool overRain) {
  if (overRain || clip.frames.size() < 3 || framesKey.empty()) return "";
  return cache.contains("plate-rain", plateRainKey(framesKey))
             ? "the plate's rain check from the cache"
             : "";
}

ParamSpec overRainParam() {
  return booleanParam("over_rain", false,
                      "also on a plate shot in rain (its own streaks, found at render time); "
                      "false: left out there, the plate shows it already");
}

}  // namespace pluvia
