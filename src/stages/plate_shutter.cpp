#include "stages/plate_shutter.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <opencv2/core.hpp>

#include "derain/motion_blur.h"
#include "image/luminance.h"
#include "pipeline/cache.h"
#include "pluvia/version.h"
#include "stages/clip_plate_rain.h"
#include "util/hash.h"
#include "util/log.h"
#include "util/parse_number.h"
#include "util/timer.h"

namespace pluvia {

namespace {

constexpr size_t kFramesMeasured = 7;  // 5 frames measured, each with a neighbour either side

std::string fraction(double seconds) {
  return fmt::format("1/{:.0f} s", 1.0 / seconds);
}

std::string halfOpenSource(double fps, const std::string& why) {
  return fmt::format("the 180-degree shutter at the plate's {:g} fps ({})", fps, why);
}

// The measurement's cache entry: the frames it is measured on. "" (not cached) without them.
std::string shutterKey(const std::string& framesKey) {
  if (framesKey.empty()) return "";
  return Hasher()
      .add("plate-shutter")
      .add(kVersion)
      .add(framesKey)
      .add(uint64_t(kFramesMeasured))
      .hex();
}

cv::Mat1f luminance(const Image& image) {
  cv::Mat1f grey(image.height, image.width);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const float* p = image.pixel(x, y);
      grey(y, x) = std::max(0.0f, rec709LuminanceFloat(p));
    }
  }
  return grey;
}

// The measured share of the frame time the shutter is open and what was seen, from the cache
// or measured on 7 frames from the middle of the clip.
derain::ShutterFromBlur measuredBlur(const ClipInfo& clip,
                                     const std::function<Image(int64_t)>& read,
                                     ArtifactCache* cache, const std::string& framesKey) {
  const std::string key = shutterKey(framesKey);
  if (cache && !key.empty()) {
    if (auto cached = cache->load("plate-shutter", key)) {
      try {
        derain::ShutterFromBlur found;
        found.measured = cached->at("measured").get<bool>();
        found.shutterFraction = cached->at("fraction").get<double>();
        found.upperBound = cached->at("upper_bound").get<bool>();
        found.stillBlurPx = cached->at("still_blur_px").get<double>();
        found.summary = cached->at("summary").get<std::string>() + ", from cache";
        return found;
      } catch (const nlohmann::json::exception&) {
        // malformed: measured again and stored over it
      }
    }
  }
  const auto started = std::chrono::steady_clock::now();
  const size_t count = std::min(clip.frames.size(), kFramesMeasured);
  const size_t first = (clip.frames.size() - count) / 2;
  std::vector<cv::Mat1f> greys;
  for (size_t i = first; i < first + count; ++i) greys.push_back(luminance(read(clip.frames[i])));
  derain::ShutterFromBlur found = derain::measureShutterFromBlur(greys);
  log::info(fmt::format("plate: shutter from the motion blur of {} frames in {:.1f} s: {}", count,
                        secondsSince(started), found.summary));
  if (cache && !key.empty())
    cache->store("plate-shutter", key,
                 {{"measured", found.measured},
                  {"fraction", found.shutterFraction},
                  {"upper_bound", found.upperBound},
                  {"still_blur_px", found.stillBlurPx},
                  {"summary", found.summary}});
  return found;
}

}  // namespace

std::optional<PlateShutter> statedShutter(const ClipInfo& clip, double fps) {
  // A field the files hold but that states no shutter is said, and the plate's shutter found as
  // if it were not there.
  const auto unusable = [&](const char* name, const std::string& text) {
    log::warning(fmt::format("plate: {} '{}' in the metadata of {} states no shutter: left out",
                             name, text, clip.path));
  };
  if (const auto it = clip.metadata.find("ExposureTime"); it != clip.metadata.end()) {
    const double seconds = parseWholeNumber<double>(it->second).value_or(0.0);
    if (std::isfinite(seconds) && seconds >= 1e-5 && seconds <= 1.0)
      return PlateShutter{seconds,
                          fmt::format("the plate's metadata (ExposureTime {:g} s)", seconds)};
    unusable("ExposureTime", it->second);
  }
  if (const auto it = clip.metadata.find("ShutterAngle"); it != clip.metadata.end()) {
    const double degrees = parseWholeNumber<double>(it->second).value_or(0.0);
    if (std::isfinite(degrees) && degrees > 0.0 && degrees <= 360.0 && fps > 0.0)
      return PlateShutter{
          degrees / 360.0 / fps,
          fmt::format("the plate's metadata (shutter angle {:g} deg at {:g} fps)", degrees, fps)};
    unusable("ShutterAngle", it->second);
  }
  return std::nullopt;
}

PlateShutter findPlateShutter(const ClipInfo& clip, double fps,
                              const std::function<Image(int64_t)>& read, ArtifactCache* cache,
                              const std::string& framesKey) {
  if (std::optional<PlateShutter> stated = statedShutter(clip, fps)) return *stated;
  if (clip.frames.size() < 3 || !read)
    return {
        0.5 / fps,
        halfOpenSource(fps, fmt::format("no shutter in its metadata, and {} no motion "
                                        "blur to measure",
                                        clip.frames.size() == 1
                                            ? std::string("a still shows")
                                            : fmt::format("{} frames show", clip.frames.size()))),
        false};
  const derain::ShutterFromBlur found = measuredBlur(clip, read, cache, framesKey);
  if (!found.measured)
    return {0.5 / fps,
            halfOpenSource(fps, "no shutter in its metadata; its motion blur: " + found.summary),
            false, found.stillBlurPx};
  const double seconds = found.shutterFraction / fps;
  return {seconds,
          fmt::format("{}measured from the plate's motion blur at {:g} fps ({})",
                      found.upperBound ? "at most, " : "", fps, found.summary),
          !found.upperBound, found.stillBlurPx};
}

const PlateShutter& clipPlateShutter(ClipContext& clip) {
  if (clip.plateShutter) return *clip.plateShutter;
  if (!clip.clip) return clip.plateShutter.emplace(PlateShutter{0.5 / clip.fps, "no plate"});
  // A proxy's frames are measured at the size they were filmed at: the blur of an edge moving
  // 2-3 px a frame is seen there and not at half the size.
  const std::function<Image(int64_t)> read =
      clip.openFilmedReader ? clip.openFilmedReader() : clip.readWorking;
  PlateShutter shutter = findPlateShutter(*clip.clip, clip.fps, read, clip.cache, clip.framesKey);
  if (shutter.firm || clip.clip->frames.size() < 3) return clip.plateShutter.emplace(shutter);
  const PlateRainFinding& rain = clipPlateRain(clip);
  const double streaks = derain::shutterFromStreaksSeconds(rain.streakElongationByLight);
  if (!rain.rained || !(streaks > 0.0) || streaks > shutter.seconds)
    return clip.plateShutter.emplace(shutter);
  return clip.plateShutter.emplace(PlateShutter{
      streaks,
      fmt::format(
          "the streaks of the plate's own rain (by their light {:.1f} times as long as "
          "wide, the median {:.1f} x {:.2f} px: (L / W - 1) D / v(D)), shorter than {} ({})",
          rain.streakElongationByLight, rain.streakLengthPx, rain.streakWidthPx,
          fraction(shutter.seconds), shutter.source),
      true, shutter.stillBlurPx});
}

double clipPlateStillBlurPx(ClipContext& clip) {
  if (clip.plateStillBlurPx) return *clip.plateStillBlurPx;
  if (!clip.clip || clip.clip->frames.size() < 3) return clip.plateStillBlurPx.emplace(0.0);
  // Where the shutter was measured the blur was measured with it; where the files state the
  // shutter it is measured here (the same 7 frames and cache entry). Both read the frames at the
  // size they were filmed at where a proxy is rendered.
  double filmedPx = clipPlateShutter(clip).stillBlurPx;
  if (statedShutter(*clip.clip, clip.fps)) {
    const std::function<Image(int64_t)> read =
        clip.openFilmedReader ? clip.openFilmedReader() : clip.readWorking;
    filmedPx = measuredBlur(*clip.clip, read, clip.cache, clip.framesKey).stillBlurPx;
  }
  return clip.plateStillBlurPx.emplace(clip.openFilmedReader ? filmedPx / clip.filmedScale
                                                             : filmedPx);
}

std::string presetShutterSource(const CameraSettings& camera, double fps) {
  if (camera.shutterAngleDeg > 0.0)
    return fmt::format("the preset's camera.shutter_angle_deg {:g} at {:g} fps",
                       camera.shutterAngleDeg, fps);
  if (camera.shutterFromPlate()) return "";
  return camera.exposureSeconds.animated() ? "the preset's camera.exposure_s keys"
                                           : "the preset's camera.exposure_s";
}

void resolvePlateShutter(CameraSettings& camera, ClipContext& clip, const char* stage) {
  std::string said;
  if (const std::string source = presetShutterSource(camera, clip.fps); !source.empty()) {
    said =
        fmt::format("shutter {} ({})", fraction(camera.exposureSecondsAt(clip.fps, 0.0)), source);
  } else {
    const PlateShutter& shutter = clipPlateShutter(clip);
    camera.plateShutterSeconds = shutter.seconds;
    said = fmt::format("shutter {}, {}; camera.exposure_s or camera.shutter_angle_deg sets another",
                       fraction(shutter.seconds), shutter.source);
  }
  // Each stage films with it, but the log says it once (the splash stage's is the rain's).
  if (said == clip.shutterSaid) {
    log::debug(fmt::format("{}: {}", stage, said));
    return;
  }
  log::info(fmt::format("{}: {}", stage, said));
  clip.shutterSaid = said;
}

}  // namespace pluvia
