#pragma once
// --skip-existing: which of a render's frames are already on disk, whole and of this preset.
#include <cstdint>
#include <string>
#include <vector>

namespace pluvia {

struct FramesToRender {
  std::vector<int64_t> frames;  // still to render, in order
  int kept = 0;                 // whole frames of this preset, left as they are
  int redone = 0;               // broken or other-preset frames, rendered again
};

// The frames of `frames` that `output` (a sequence pattern, a movie or one image file) does not
// yet hold whole with `presetHash` (io/written_frame.h), each frame rendered again named in a
// warning. A movie is kept or redone whole. Checks files only: nothing is decoded from the input.
FramesToRender framesStillToRender(const std::string& output, const std::vector<int64_t>& frames,
                                   const std::string& presetHash);

}  // namespace pluvia
