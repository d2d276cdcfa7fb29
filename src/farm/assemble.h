#pragma once
// A farm job's last step for a movie output: the frames its chunks rendered (a 16-bit TIFF
// sequence, farm/farm_job.h) encoded into the movie by the project's movie writer, as a
// one-machine render would have encoded them.
#include <cstdint>
#include <string>

#include "io/clip_writer.h"
#include "io/output_target.h"

namespace pluvia::farm {

// Encodes frames first..last of the sequence `frames` into `movie` (under the movie's output
// lock; its pixels are passed as read, no colour conversion: the chunks wrote them in the
// movie's encoding). Throws pluvia::Error naming the first missing frame's file before anything
// is encoded, and refuses a movie that is one of the frame files. Returns the frames encoded.
int assembleMovie(const std::string& frames, int64_t first, int64_t last, const OutputTarget& movie,
                  const WriterOptions& options);

}  // namespace pluvia::farm
