#pragma once
// A movie encoded by an ffmpeg process fed frames through a pipe: H.264, ProRes or DNxHR
// (WriterOptions::codec), with colour tags, converted to YUV with the tagged matrix. 8-bit codecs
// (H.264, DNxHR HQ) get 8-bit Y'CbCr made by pluvia, deeper ones 16-bit RGB.
#include <memory>
#include <string>
#include <vector>

#include "io/clip_writer.h"

namespace pluvia {

// Containers the movie writer produces, lower case.
const std::vector<std::string>& movieOutputExtensions();
// Codecs WriterOptions::codec may name.
std::vector<std::string> movieCodecs();
// Those that carry an alpha channel (ProRes 4444).
std::vector<std::string> codecsWithAlpha();

// `withAlpha`: the frames' alpha goes into the movie too (a codec of codecsWithAlpha(), else an
// error naming `path`).
std::unique_ptr<ClipWriter> openMovieWriter(const std::string& path, int width, int height,
                                            const WriterOptions& options, bool withAlpha);

}  // namespace pluvia
