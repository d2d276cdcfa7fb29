// Derain and matte extraction: rain strokes cut from the user's own rain footage.
// This version is the Starik–Werman baseline (temporal median background, matte from
// the positive residual, strokes as elongated connected components, rain assumed vertical);
// the stroke-extraction issue replaces the matte solve with Wang et al.'s Eq. (1).
#include <algorithm>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "io/clip_reader.h"
#include "pipeline/cache.h"
#include "pluvia/version.h"
#include "rain/stroke_library.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/hash.h"
#include "util/log.h"

namespace pluvia {
namespace {

constexpr const char* kStageVersion = "1";
constexpr int kCellWidth = 8;
constexpr int kCellHeight = 64;

cv::Mat grayOf(const Image& image) {
  cv::Mat gray(image.height, image.width, CV_32F);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const float* p = image.pixel(x, y);
      gray.at<float>(y, x) = 0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2];
    }
  return gray;
}

cv::Mat temporalMedian(const std::vector<cv::Mat>& frames) {
  cv::Mat median(frames[0].size(), CV_32F);
  std::vector<float> values(frames.size());
  for (int y = 0; y < median.rows; ++y)
    for (int x = 0; x < median.cols; ++x) {
      for (size_t k = 0; k < frames.size(); ++k) values[k] = frames[k].at<float>(y, x);
      std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
      median.at<float>(y, x) = values[values.size() / 2];
    }
  return median;
}

struct Candidate {
  cv::Mat matte;  // kCellWidth x kCellHeight, peak 1
  double score;
};

// Cuts elongated bright residual blobs out of one frame's matte.
void cutStrokes(const cv::Mat& alpha, std::vector<Candidate>& out) {
  cv::Mat mask = alpha > 0.04f;
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  for (int label = 1; label < n; ++label) {
    const int x = stats.at<int>(label, cv::CC_STAT_LEFT), y = stats.at<int>(label, cv::CC_STAT_TOP);
    const int w = stats.at<int>(label, cv::CC_STAT_WIDTH), h = stats.at<int>(label, cv::CC_STAT_HEIGHT);
    const bool touchesEdge = x == 0 || y == 0 || x + w == alpha.cols || y + h == alpha.rows;
    if (touchesEdge || h < 12 || h < 2.5 * w) continue;
    cv::Rect box(std::max(0, x - 2), y, std::min(alpha.cols - std::max(0, x - 2), w + 4), h);
    cv::Mat crop = alpha(box).clone();
    crop.setTo(0, labels(box) != label);
    double peak;
    cv::minMaxLoc(crop, nullptr, &peak);
    cv::Mat cell;
    cv::resize(crop, cell, cv::Size(kCellWidth, kCellHeight), 0, 0, cv::INTER_AREA);
    double cellPeak;
    cv::minMaxLoc(cell, nullptr, &cellPeak);
    if (cellPeak <= 0) continue;
    cell /= cellPeak;
    out.push_back({cell, double(h) * cv::mean(crop)[0] / std::max(1, w)});
  }
}

std::string derainInput(const Preset& p, const ClipInfo& clip) {
  return p.string("derain.input").empty() ? clip.path : p.string("derain.input");
}

std::string derainCacheKey(const Preset& p, const ClipInfo& clip) {
  return Hasher().add("derain").add(kStageVersion).add(kVersion).add(p.at("derain").dump()).add(derainInput(p, clip)).hex();
}

class DerainStage : public Stage {
 public:
  explicit DerainStage(const Preset& p)
      : window_(int(p.number("derain.frames"))), count_(int(p.number("derain.count"))) {}

  void prepare(ClipContext& clip) override {
    const std::string input = derainInput(*clip.preset, *clip.clip);
    const std::string key = derainCacheKey(*clip.preset, *clip.clip);
    if (clip.cache) {
      if (auto cached = clip.cache->load("derain", key)) {
        clip.footageStrokes = rain::strokeAtlasFromJson(*cached, clip.cache->pathFor("derain", key).string());
        return;
      }
    }
    auto reader = openClip(input);
    const auto& frames = reader->info().frames;
    if (frames.size() < 3) {
      throw Error(fmt::format("derain needs at least 3 frames, {} has {}", input, frames.size()), {"derain", {}, input});
    }
    std::vector<cv::Mat> grays;
    for (size_t i = 0; i < std::min<size_t>(frames.size(), size_t(window_)); ++i) grays.push_back(grayOf(reader->read(frames[i])));
    cv::Mat background = temporalMedian(grays);
    std::vector<Candidate> candidates;
    for (const auto& gray : grays) {
      cv::Mat residual = cv::max(gray - background, 0.0f);
      cv::Mat headroom = cv::max(1.0f - background, 0.05f);
      cv::Mat alpha = residual / headroom;
      cutStrokes(alpha, candidates);
    }
    if (candidates.empty()) throw Error("no rain strokes found in the footage", {"derain", {}, input});
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    candidates.resize(std::min<size_t>(candidates.size(), size_t(count_)));
    gpu::StrokeAtlas atlas;
    atlas.width = kCellWidth * int(candidates.size());
    atlas.height = kCellHeight;
    atlas.alpha.assign(size_t(atlas.width) * atlas.height, 0.0f);
    for (size_t s = 0; s < candidates.size(); ++s) {
      for (int y = 0; y < kCellHeight; ++y)
        for (int x = 0; x < kCellWidth; ++x)
          atlas.alpha[size_t(y) * atlas.width + s * kCellWidth + x] = candidates[s].matte.at<float>(y, x);
      atlas.rects.push_back({float(s * kCellWidth), 0.0f, float((s + 1) * kCellWidth), float(kCellHeight)});
    }
    log::info(fmt::format("derain: {} strokes cut from {} frames of {}", atlas.rects.size(), grays.size(), input));
    if (clip.cache) clip.cache->store("derain", key, rain::strokeAtlasToJson(atlas));
    clip.footageStrokes = std::move(atlas);
  }

 private:
  int window_;
  int count_;
};

}  // namespace

StageInfo derainStageInfo() {
  StageInfo info;
  info.spec.name = "derain";
  info.spec.help = "Cuts rain strokes out of real rain footage (used when rain.strokes is \"derain\").";
  info.spec.outputs = {"footage_strokes"};
  info.spec.params = {
      {"enabled", ParamType::Boolean, true, {}, {}, {}, "", "run this stage when its strokes are read"},
      {"input", ParamType::String, "", {}, {}, {}, "", "rain footage to cut strokes from; empty: the render input"},
      {"frames", ParamType::Integer, 20, 3, 1000, {}, "frames", "frames in the analysis window"},
      {"count", ParamType::Integer, 64, 1, 4096, {}, "strokes", "strokes kept, best first"},
  };
  info.perClip = true;
  info.cacheKey = derainCacheKey;
  info.create = [](const Preset& p) { return std::make_unique<DerainStage>(p); };
  return info;
}

}  // namespace pluvia
