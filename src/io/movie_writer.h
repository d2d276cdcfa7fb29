#pragma once
// A movie encoded by an ffmpeg process (libx264, yuv420p) fed 16-bit RGB frames through a pipe.
#include <memory>
#include <string>
#include <vector>

#include "io/clip_writer.h"

namespace pluvia {

// Containers the movie writer produces, lower case.
const std::vector<std::string>& movieOutputExtensions();

std::unique_ptr<ClipWriter> openMovieWriter(const std::string& path, int width, int height,
                                            const WriterOptions& options);

}  // namespace pluvia
