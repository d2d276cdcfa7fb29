#include "stages/clip_still.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include <opencv2/imgproc.hpp>

#include <fmt/format.h>

#include "geometry/sky_mask.h"
#include "image/resize.h"
#include "pipeline/cache.h"
#include "pluvia/version.h"
#include "util/hash.h"
#include "util/log.h"
#include "util/median.h"
#include "util/parallel.h"
#include "util/timer.h"

namespace pluvia {
namespace {

constexpr int kStillFrames = 5;
// The sky is found at this longest side, whatever the plate's size: the texture test and the
// seed and speck sizes are in pixels, so a proxy render and the full one find the same sky,
// and a 4K plate does not cost seconds for a mask that needs no such detail.
constexpr int kSkySidePx = 480;
// A pixel of a frame this many display codes (8-bit grey, rain filtered out) off the still's
// shows something else there: the camera moved, or something passed.
constexpr int kMovedCodes = 20;
// The sky finder's version in its cache key: a cache made by an earlier one holds its mask.
// 2: a cloud's wisps are no wall's specks, warm colours (brick) are no sky, and the sky reaches a
// roof line past the texture test. 3: the sky sits at display code 140 or more (a road seen from
// above is none).
constexpr uint64_t kSkyVersion = 3;

// The still's entry: the frames it is made of and how many it takes. Empty (not cached) when
// the session gives no key for its frames.
std::string stillKeyOf(const std::string& framesKey) {
  if (framesKey.empty()) return "";
  return Hasher().add("still").add(kVersion).add(framesKey).add(uint64_t(kStillFrames)).hex();
}

std::string stillKey(const ClipContext& clip) {
  return stillKeyOf(clip.framesKey);
}

// The sky's: the still's, and the camera that places the horizon.
std::string skyKey(const ClipContext& clip, const Camera& camera) {
  const std::string still = stillKey(clip);
  if (still.empty()) return "";
  Hasher hasher;
  hasher.add("sky").add(kSkyVersion).add(still).add(uint64_t(kSkySidePx));
  hasher.add(uint64_t(camera.width)).add(uint64_t(camera.height));
  for (double value : {camera.focalPx, camera.cx, camera.cy}) hasher.add(value);
  for (int i = 0; i < 9; ++i) hasher.add(camera.worldFromCamera(i / 3, i % 3));
  for (int i = 0; i < 3; ++i) hasher.add(camera.positionMeters(i));
  return hasher.hex();
}

// `image`'s linear RGB at the size the sky is found at (its longest side kSkySidePx).
cv::Mat atSkySize(const Image& image, int interpolation) {
  const double scale = double(kSkySidePx) / std::max(image.width, image.height);
  cv::Mat small;
  cv::resize(rgbMat(image), small, scaledSize(image.width, image.height, scale), 0, 0,
             interpolation);
  return small;
}

// Up to `maxFrames` of `frames`, spread evenly over them (the first included): the frames a
// still is the median of.
std::vector<int64_t> spreadFrames(const std::vector<int64_t>& frames, int maxFrames) {
  const int count = std::max(1, std::min<int>(maxFrames, int(frames.size())));
  std::vector<int64_t> spread;
  for (int s = 0; s < count; ++s)
    spread.push_back(frames[frames.size() * size_t(s) / size_t(count)]);
  return spread;
}

}  // namespace

Image medianOfFrames(ClipContext& clip, const std::vector<int64_t>& frames, int maxFrames) {
  const std::vector<int64_t> spread = spreadFrames(frames, maxFrames);
  const int count = int(spread.size());
  if (clip.reader) clip.reader->prefetch(spread);
  std::vector<Image> images;
  for (int64_t frame : spread) images.push_back(clip.readWorking(frame));
  Image median = images.front();
  if (count < 3) return median;
  // Samples in parallel blocks (a 1080p still is 8 million of them).
  if (count == 5) {
    forEachBlock(median.rgba.size(), 1 << 16, [&](size_t begin, size_t end) {
      const float *a = images[0].rgba.data(), *b = images[1].rgba.data(),
                  *c = images[2].rgba.data(), *d = images[3].rgba.data(),
                  *e = images[4].rgba.data();
      for (size_t i = begin; i < end; ++i) median.rgba[i] = median5(a[i], b[i], c[i], d[i], e[i]);
    });
    return median;
  }
  forEachBlock(median.rgba.size(), 1 << 16, [&](size_t begin, size_t end) {
    std::vector<float> values(static_cast<size_t>(count));
    for (size_t i = begin; i < end; ++i) {
      for (int s = 0; s < count; ++s) values[size_t(s)] = images[size_t(s)].rgba[i];
      median.rgba[i] = medianInPlace(values.data(), values.size());
    }
  });
  return median;
}

const Image& clipStill(ClipContext& clip) {
  if (clip.still) return *clip.still;
  const std::string key = stillKey(clip);
  if (clip.cache && !key.empty()) {
    if (auto blob = clip.cache->loadBlob("still", key)) {
      // An entry of another size (edited, or written by another build) is made again.
      if (blob->pixelSize(4 * sizeof(float)) == std::pair{clip.clip->width, clip.clip->height}) {
        Image& still = clip.still.emplace(clip.clip->width, clip.clip->height);
        std::memcpy(still.rgba.data(), blob->bytes.data(), blob->bytes.size());
        log::info("still: the median of the clip's frames, from cache");
        return still;
      }
      log::warning(fmt::format("ignoring cache entry {}: not a still of the frames' {}x{} px",
                               clip.cache->pathFor("still", key).string(), clip.clip->width,
                               clip.clip->height));
    }
  }
  const auto started = std::chrono::steady_clock::now();
  clip.still = medianOfFrames(clip, clip.clip->frames, kStillFrames);
  log::debug(fmt::format("still: the median of {} frames in {:.2f} s", kStillFrames,
                         secondsSince(started)));
  if (clip.cache && !key.empty())
    clip.cache->storeBlob("still", key,
                          {{"width", clip.still->width}, {"height", clip.still->height}},
                          clip.still->rgba.data(), clip.still->rgba.size() * sizeof(float));
  return *clip.still;
}

SmallSky smallSkyOf(const Image& image, const Camera& camera) {
  const bool shrinks = std::max(image.width, image.height) > kSkySidePx;
  const cv::Mat small = atSkySize(image, shrinks ? cv::INTER_AREA : cv::INTER_LINEAR);
  cv::Mat bgr;
  cv::cvtColor(small, bgr, cv::COLOR_RGB2BGR);
  SmallSky out;
  out.sky = estimateSkyMask(bgr, camera);
  cv::cvtColor(small, out.grey, cv::COLOR_RGB2GRAY);
  return out;
}

std::vector<uint8_t> fullSizeSky(const cv::Mat& small, int width, int height) {
  cv::Mat sky;
  cv::resize(small, sky, cv::Size(width, height), 0, 0, cv::INTER_NEAREST);
  std::vector<uint8_t> mask(size_t(width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) mask[size_t(y) * width + x] = sky.at<uchar>(y, x) ? 1 : 0;
  return mask;
}

std::vector<uint8_t> skyInImage(const Image& image, const Camera& camera) {
  return fullSizeSky(smallSkyOf(image, camera).sky, image.width, image.height);
}

double stillMismatch(ClipContext& clip) {
  // Kept beside the still: a render chunk after `pluvia prepare` decodes none of its frames.
  const std::string still = stillKey(clip);
  const std::string key = still.empty() ? "" : Hasher().add("still-motion").add(still).hex();
  if (clip.cache && !key.empty())
    if (auto cached = clip.cache->load("still-motion", key)) {
      // A malformed entry (edited, cut short) is measured again and stored over.
      if (cached->is_object() && cached->contains("mismatch") && cached->at("mismatch").is_number())
        return cached->at("mismatch").get<double>();
      log::warning(fmt::format("ignoring cache entry {}: no \"mismatch\" number",
                               clip.cache->pathFor("still-motion", key).string()));
    }
  // Grey display codes at the sky's size, 5x5 median-filtered: thin rain streaks and noise
  // leave, a moved picture stays.
  const auto grey = [](const Image& image) {
    cv::Mat small, codes;
    cv::cvtColor(atSkySize(image, cv::INTER_AREA), small, cv::COLOR_RGB2GRAY);
    cv::max(small, 0.0, small);
    cv::pow(small, 1.0 / 2.2, small);
    small.convertTo(codes, CV_8U, 255.0);
    cv::medianBlur(codes, codes, 5);
    return codes;
  };
  const cv::Mat stillGrey = grey(clipStill(clip));
  double worst = 0.0;
  for (int64_t frame : spreadFrames(clip.clip->frames, kStillFrames)) {
    cv::Mat difference;
    cv::absdiff(grey(clip.readWorking(frame)), stillGrey, difference);
    worst = std::max(
        worst, double(cv::countNonZero(difference > kMovedCodes)) / double(difference.total()));
  }
  if (clip.cache && !key.empty()) clip.cache->store("still-motion", key, {{"mismatch", worst}});
  return worst;
}

const std::vector<uint8_t>& clipSky(ClipContext& clip, const Camera& camera) {
  if (clip.stillSky) return *clip.stillSky;
  const std::string key = skyKey(clip, camera);
  if (clip.cache && !key.empty()) {
    if (auto blob = clip.cache->loadBlob("sky", key)) {
      const Image& still = clipStill(clip);
      if (blob->pixelSize(1) == std::pair{still.width, still.height}) {
        log::info("sky: found in the still, from cache");
        return clip.stillSky.emplace(blob->bytes.begin(), blob->bytes.end());
      }
    }
  }
  clip.stillSky = skyInImage(clipStill(clip), camera);
  if (clip.cache && !key.empty())
    clip.cache->storeBlob("sky", key,
                          {{"width", clip.still->width}, {"height", clip.still->height}},
                          clip.stillSky->data(), clip.stillSky->size());
  return *clip.stillSky;
}

std::string cachedStillNote(const std::string& framesKey, const ArtifactCache& cache) {
  if (framesKey.empty()) return "";
  return cache.contains("still", stillKeyOf(framesKey)) ? "the still from the cache" : "";
}

}  // namespace pluvia
