#pragma once
// The frame sizes pluvia reads: a header is checked before any pixel is allocated, so a 1 KB
// file that claims 100000x100000 pixels (a decompression bomb, a corrupt header) is refused at
// once with its size named, instead of taking gigabytes and failing in the allocator; and a
// frame too small to analyse (1x5000) is refused before an OpenCV assertion.
#include <cstdint>
#include <string>

#include "util/error.h"

namespace pluvia {

constexpr int kMaxFrameSidePx = 32768;
// 16384 x 8192 (a 16K panorama): a float RGBA frame of 2 GiB.
constexpr int64_t kMaxFramePixels = int64_t(1) << 27;

// Throws pluvia::Error naming `path` (and `context`'s frame) when width x height is over the
// limits above: every image and movie read is checked so.
void checkFrameSize(int64_t width, int64_t height, const std::string& path,
                    const ErrorContext& context);

}  // namespace pluvia
