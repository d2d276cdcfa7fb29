#pragma once
// --skip-existing: which of a render's frames are already on disk, whole and alike.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "io/output_target.h"

namespace pluvia {

struct FramesToRender {
  std::vector<int64_t> frames;  // still to render, in order
  int kept = 0;                 // whole frames of this preset, left as they are
  int redone = 0;               // broken or other-preset frames, rendered again
};

// The frames of `frames` that `output` (a sequence pattern, a movie or one image file) does not
// yet hold whole with the identity this render's header `metadata` records (preset, plate, size,
// proxy, colour, AOVs, format: io/written_frame.h), each frame rendered again named in a warning
// with what differs. A movie is kept or redone whole, with the AOV movies beside it (`aovs`), and
// only at the size this render writes (`size`, "WIDTHxHEIGHT": a proxy's movie is not kept as
// the final). Checks files only: nothing is decoded from the input.
FramesToRender framesStillToRender(const OutputTarget& output, const std::vector<int64_t>& frames,
                                   const std::map<std::string, std::string>& metadata,
                                   const std::vector<std::string>& aovs, const std::string& size);

}  // namespace pluvia
