#pragma once
// Checking a frame file that an earlier run left, before `--skip-existing` keeps it.
#include <string>

namespace pluvia {

// Returns why the file at `path` must be rendered again, or "" when it can be kept: it is
// empty, it does not decode completely (truncated, corrupt), or it records a
// "pluvia:presetHash" other than `presetHash` (a frame of another preset or seed). Formats that
// hold pluvia's metadata (EXR, PNG, TIFF, JPEG) must carry the hash; DPX and HDR hold none, so
// there only the decode is checked.
std::string reasonToRenderAgain(const std::string& path, const std::string& presetHash);

}  // namespace pluvia
