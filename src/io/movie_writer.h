#pragma once
// A movie encoded by an ffmpeg process fed 16-bit RGB frames through a pipe: H.264, ProRes or
// DNxHR (WriterOptions::codec), with colour tags, converted to YUV with the tagged matrix.
#include <memory>
#include <string>
#include <vector>

#include "io/clip_writer.h"

namespace pluvia {

// Containers the movie writer produces, lower case.
const std::vector<std::string>& movieOutputExtensions();
// Codecs WriterOptions::codec may name.
std::vector<std::string> movieCodecs();

std::unique_ptr<ClipWriter> openMovieWriter(const std::string& path, int width, int height,
                                            const WriterOptions& options);

}  // namespace pluvia
