#pragma once
// Opening the input with a per-clip cache: a movie's frame count, which its opening checks by
// decoding from the last frame its container lists (io/movie_reader.h), is kept in the cache
// under the file's identity, so that a farm's chunks after `pluvia prepare` (each its own
// process) do not each decode the movie's last GOP again.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "io/clip_reader.h"

namespace pluvia {

// openNumberedClip(input, movieFirstFrame), the movie's checked frame count taken from and kept
// in `cacheDir` (empty: no cache, as openNumberedClip). An entry that is not a count, or one
// shorter than the container's own count, is ignored with a warning, and the count checked again
// replaces it.
std::unique_ptr<ClipReader> openNumberedClipWithCache(const std::string& input,
                                                      std::optional<int64_t> movieFirstFrame,
                                                      const std::string& cacheDir);

}  // namespace pluvia
