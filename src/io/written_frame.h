#pragma once
// Checking a frame file that an earlier run left, before `--skip-existing` keeps it.
#include <cstddef>
#include <string>

namespace pluvia {

// Returns why the file at `path` must be rendered again, or "" when it can be kept: it is
// empty, it does not decode completely (truncated, corrupt), or it records a
// "pluvia:presetHash" other than `presetHash` (a frame of another preset or seed). Formats that
// hold pluvia's metadata (EXR, PNG, TIFF, JPEG) must carry the hash; DPX and HDR hold none, so
// there only the decode is checked.
std::string reasonToRenderAgain(const std::string& path, const std::string& presetHash);

// The same for a movie a previous run left: it must open and hold `frames` frames (its preset
// is not checked: the hash sits in a comment that OpenCV does not read).
std::string reasonToRenderMovieAgain(const std::string& path, size_t frames);

}  // namespace pluvia
