#pragma once
// Checking a frame file that an earlier run left, before `--skip-existing` keeps it.
#include <cstddef>
#include <map>
#include <string>

namespace pluvia {

// The header keys that identify what a frame is (pipeline/render_job.cpp): its preset and seed,
// pluvia's version, the plate, the output size, a proxy's scale, the colour, the AOVs and the
// file format's options.
extern const char* const kResumeIdentityKeys[8];

// Returns why the file at `path` must be rendered again, or "" when it can be kept: it is
// empty, it does not decode completely (truncated, corrupt), or one of kResumeIdentityKeys
// differs from what `metadata` (this render's header) says, named with both values: a frame
// of another preset or seed, another plate, a proxy, another colour config... A key this render
// does not write (pluvia:proxy on a final) must be absent. Formats that hold pluvia's metadata
// (EXR, PNG, TIFF, JPEG) must carry the keys; DPX and HDR hold none, so there only the decode is
// checked.
std::string reasonToRenderAgain(const std::string& path,
                                const std::map<std::string, std::string>& metadata);

// The same for a movie a previous run left: it must be whole (io/movie_index.h), open, be
// `size` ("WIDTHxHEIGHT", the output's; a proxy's movie is not the final's) and hold `frames`
// frames (its preset is not checked: the hash sits in a comment that OpenCV does not read).
std::string reasonToRenderMovieAgain(const std::string& path, size_t frames,
                                     const std::string& size);

}  // namespace pluvia
