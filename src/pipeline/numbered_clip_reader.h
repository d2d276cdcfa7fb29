#pragma once
// `--start-frame`: a movie's frames numbered from the plate's own first frame (1001, 86400)
// rather than from 0, so that its frames are asked for, rendered (the same rain as the sequence
// of those numbers), named and timecoded by the numbers the facility uses.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "io/clip_reader.h"

namespace pluvia {

// Opens `input`; with `movieFirstFrame`, a movie's frame 0 becomes frame *movieFirstFrame. A
// sequence or image keeps its own numbers: asking to renumber one is a usage error naming it.
std::unique_ptr<ClipReader> openNumberedClip(const std::string& input,
                                             std::optional<int64_t> movieFirstFrame);

}  // namespace pluvia
