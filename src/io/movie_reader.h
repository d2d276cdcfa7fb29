#pragma once
// A movie file decoded through OpenCV's FFmpeg backend (8-bit RGB, frames numbered 0..N-1).
#include <memory>
#include <string>

#include "io/clip_reader.h"

namespace pluvia {

std::unique_ptr<ClipReader> openMovie(const std::string& path);

}  // namespace pluvia
