// Derain and stroke extraction: rain strokes cut from the user's own rain footage (Wang et al.
// section 2). The first derain.frames frames of the footage are solved as one window with
// Eq. (1) (src/derain/clip_derain.h) and single strokes are cut from their mattes
// (src/derain/stroke_extraction.h); `pluvia strokes` does the same over a whole clip and writes
// a library file.
#include <algorithm>

#include <fmt/format.h>

#include "derain/clip_derain.h"
#include "derain/stroke_extraction.h"
#include "io/clip_reader.h"
#include "pipeline/cache.h"
#include "pluvia/version.h"
#include "rain/stroke_library.h"
#include "stages/derain_settings.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/hash.h"
#include "util/log.h"

namespace pluvia {
namespace {

constexpr const char* kStageVersion = "2";

std::string derainInput(const DerainSettings& derain, const ClipInfo& clip) {
  return derain.input.empty() ? clip.path : derain.input;
}

std::string derainCacheKey(const DerainSettings& derain, const ClipInfo& clip) {
  return Hasher()
      .add("derain")
      .add(kStageVersion)
      .add(kVersion)
      .add(derain.resolved.dump())
      .add(derainInput(derain, clip))
      .hex();
}

class DerainStage : public Stage {
 public:
  explicit DerainStage(DerainSettings derain) : derain_(std::move(derain)) {}

  void prepare(ClipContext& clip) override {
    const std::string input = derainInput(derain_, *clip.clip);
    const std::string key = derainCacheKey(derain_, *clip.clip);
    if (clip.cache) {
      if (auto cached = clip.cache->load("derain", key)) {
        try {
          clip.footageStrokes =
              rain::strokeAtlasFromJson(*cached, clip.cache->pathFor("derain", key).string());
          return;
        } catch (const Error& e) {
          // A malformed entry (edited, cut short) is derained again and stored over.
          log::warning(fmt::format("ignoring cache entry: {}", e.describe()));
        }
      }
    }
    // One window: the first derain.frames frames of the footage.
    const std::vector<int64_t> frames = openClip(input)->info().frames;
    if (frames.size() < 3) {
      throw Error(fmt::format("derain needs at least 3 frames, {} has {}", input, frames.size()),
                  {"derain", {}, input});
    }
    derain::ClipDerainSettings settings;
    settings.window = int(std::min<size_t>(frames.size(), size_t(derain_.frames)));
    settings.firstFrame = frames.front();
    settings.lastFrame = frames[size_t(settings.window) - 1];

    derain::StrokeExtractionSettings extraction;
    extraction.count = derain_.strokeCount;
    derain::ClipStrokes cut = derain::cutStrokesFromClip(input, settings, extraction);
    if (cut.library.strokes.empty()) {
      throw Error(fmt::format("no rain strokes found in {} (frames {}-{}, {}); set derain.input "
                              "to rain footage, or rain.strokes to builtin",
                              input, settings.firstFrame, settings.lastFrame, cut.angleDescription),
                  {"derain", {}, input});
    }
    log::info(fmt::format("derain: {} strokes kept of {} candidates from frames {}-{} of {}, {}",
                          cut.library.strokes.size(), cut.candidates, settings.firstFrame,
                          settings.lastFrame, input, cut.angleDescription));
    if (clip.cache) clip.cache->store("derain", key, rain::strokeAtlasToJson(cut.library.atlas));
    clip.footageStrokes = std::move(cut.library.atlas);
  }

 private:
  DerainSettings derain_;
};

}  // namespace

StageInfo derainStageInfo() {
  return makeStageInfo(
      derainTable().section(), derainSettings,
      {.perClip = true,
       .cacheKey = [](const DerainSettings& derain, const Preset&,
                      const ClipInfo& clip) { return derainCacheKey(derain, clip); },
       .create = [](const DerainSettings& derain,
                    const Preset&) { return std::make_unique<DerainStage>(derain); }});
}

}  // namespace pluvia
