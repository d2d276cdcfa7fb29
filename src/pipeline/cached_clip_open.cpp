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
  const std::optional<nlohmann::json> entry = cache.load(kStage, key);
  const nlohmann::json cached =
      entry && entry->is_object() ? entry->value("frames", nlohmann::json()) : nlohmann::json();
  const bool aCount = cached.is_number_integer() && cached >= 1 && cached <= kMaxFrames;
  // Taken as checked; the reader still refuses a count its container says is short.
  const bool taken = aCount && !checkedMovieFrames(input);
  if (taken) rememberCheckedMovieFrames(input, cached.get<int64_t>());
  std::unique_ptr<ClipReader> reader = openNumberedClip(input, movieFirstFrame);
  const std::optional<int64_t> frames = checkedMovieFrames(input);
  if (!frames) return reader;
  if (cached == *frames) {
    if (taken) log::debug(fmt::format("{}: {} frames, from cache", input, *frames));
  } else {
    // Missing, or another value (an entry edited or cut short): the checked count replaces it.
    if (entry)
      log::warning(fmt::format("ignoring cache entry {}: not the movie's frame count ({})",
                               cache.pathFor(kStage, key).string(), *frames));
    cache.store(kStage, key, {{"frames", *frames}});
  }
  return reader;
}

}  // namespace pluvia
