#include "stages/clip_plate_rain.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "derain/plate_rain.h"
#include "image/srgb.h"
#include "pipeline/cache.h"
#include "pluvia/version.h"
#include "util/hash.h"
#include "util/log.h"
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

}  // namespace

const PlateRainFinding& clipPlateRain(ClipContext& clip) {
  if (clip.plateRain) return *clip.plateRain;
  PlateRainFinding finding;
  if (!clip.clip || !clip.readWorking || clip.clip->frames.size() < 3) {
    finding.summary = "fewer than 3 frames to measure: taken as dry";
    return clip.plateRain.emplace(finding);
  }
  const std::string key = plateRainKey(clip.framesKey);
  if (clip.cache && !key.empty()) {
    if (auto cached = clip.cache->load("plate-rain", key)) {
      try {
        finding.rained = cached->at("rained").get<bool>();
        finding.summary = cached->at("summary").get<std::string>();
        log::info(fmt::format("plate: {} in rain: {}, from cache",
                              finding.rained ? "shot" : "not shot", finding.summary));
        return clip.plateRain.emplace(finding);
      } catch (const nlohmann::json::exception&) {
        // Malformed: measured again and stored over it.
      }
    }
  }
  const std::vector<int64_t>& frames = clip.clip->frames;
  const auto start = std::chrono::steady_clock::now();
  const size_t count = std::min(frames.size(), kFramesRead);
  const size_t first = (frames.size() - count) / 2;
  std::vector<cv::Mat3f> codes;
  for (size_t i = first; i < first + count; ++i)
    codes.push_back(displayCodes(clip.readWorking(frames[i])));
  const derain::PlateRain rain = derain::measurePlateRain(codes);
  finding.rained = rain.rained;
  finding.summary = rain.summary();
  log::info(fmt::format("plate: {} in rain: {}, in {:.1f} s", rain.rained ? "shot" : "not shot",
                        finding.summary, secondsSince(start)));
  if (clip.cache && !key.empty())
    clip.cache->store("plate-rain", key,
                      {{"rained", finding.rained}, {"summary", finding.summary}});
  return clip.plateRain.emplace(finding);
}

bool leaveOutOnRainedPlate(ClipContext& clip, const std::string& stage, bool overRain) {
  if (overRain || !clipPlateRain(clip).rained) return false;
  log::info(fmt::format(
      "{0}: left out: the plate was shot in rain and holds its own veil; {0}.over_rain = true "
      "adds it anyway",
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
                      "false: left out there, the plate holds its own veil");
}

}  // namespace pluvia
