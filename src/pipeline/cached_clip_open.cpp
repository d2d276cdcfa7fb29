#include "pipeline/cached_clip_open.h"

#include <fmt/format.h>

#include "io/movie_reader.h"
#include "io/sequence_pattern.h"
#include "pipeline/cache.h"
#include "pipeline/numbered_clip_reader.h"
#include "util/hash.h"
#include "util/log.h"

namespace pluvia {
namespace {

constexpr const char* kStage = "movie-frames";
constexpr int64_t kMaxFrames = 100000000;  // a count past this is no count (an edited entry)

}  // namespace

std::unique_ptr<ClipReader> openNumberedClipWithCache(const std::string& input,
                                                      std::optional<int64_t> movieFirstFrame,
                                                      const std::string& cacheDir) {
  const std::optional<std::string> identity =
      !cacheDir.empty() && isMovieExtension(input) ? movieFileIdentity(input) : std::nullopt;
  if (!identity) return openNumberedClip(input, movieFirstFrame);
  const ArtifactCache cache(cacheDir);
  const std::string key = Hasher().add(kStage).add(*identity).hex();
  bool cached = false;
  if (!checkedMovieFrames(input)) {
    if (auto entry = cache.load(kStage, key)) {
      const auto frames = entry->find("frames");
      cached = frames != entry->end() && frames->is_number_integer() && *frames >= 1 &&
               *frames <= kMaxFrames;
      if (cached) {
        rememberCheckedMovieFrames(input, frames->get<int64_t>());
        log::debug(fmt::format("{}: {} frames, from cache", input, frames->get<int64_t>()));
      } else {
        log::warning(fmt::format("ignoring cache entry {}: not a frame count",
                                 cache.pathFor(kStage, key).string()));
      }
    }
  }
  std::unique_ptr<ClipReader> reader = openNumberedClip(input, movieFirstFrame);
  // Stored when the cache lacks it or holds something else (an entry edited or cut short).
  if (const std::optional<int64_t> frames = checkedMovieFrames(input); frames && !cached) {
    const auto entry = cache.load(kStage, key);
    if (!entry || entry->value("frames", nlohmann::json()) != *frames)
      cache.store(kStage, key, {{"frames", *frames}});
  }
  return reader;
}

}  // namespace pluvia
