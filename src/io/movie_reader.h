#pragma once
// A movie file decoded by an ffmpeg process at its own bit depth (8-bit movies as 8-bit codes,
// deeper ones through 16 bits), frames numbered 0..N-1 at the nominal rate; a variable-rate
// movie is conformed to that rate, with a warning.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "io/clip_reader.h"

namespace pluvia {

std::unique_ptr<ClipReader> openMovie(const std::string& path);

// Opening a movie checks its frame count by decoding from the last frame its container lists
// (a whole long GOP). The counts checked are kept per process under the file's identity (its
// absolute path, size and modification time: a file written again is checked again); a count
// taken from elsewhere (a per-clip cache another process filled) is remembered the same way, and
// the next opening of that file then decodes nothing to count.
std::optional<std::string> movieFileIdentity(const std::string& path);  // nullopt: unreadable
std::optional<int64_t> checkedMovieFrames(const std::string& path);
void rememberCheckedMovieFrames(const std::string& path, int64_t frames);

}  // namespace pluvia
