#pragma once
// A movie file decoded by an ffmpeg process at its own bit depth (8-bit movies as 8-bit codes,
// deeper ones through 16 bits), frames numbered 0..N-1 at the nominal rate; a variable-rate
// movie is conformed to that rate, with a warning.
#include <memory>
#include <string>

#include "io/clip_reader.h"

namespace pluvia {

std::unique_ptr<ClipReader> openMovie(const std::string& path);

}  // namespace pluvia
