#pragma once
// A night plate's lamps are the light itself, not a surface the rain wets or a scene behind the
// rain. A clipped core stands for a radiance far over the clip (a street lamp's bulb is
// thousands of times a night scene's grey), so the rain's few per cent of darkening and
// extinction leave it clipped; its glow is its light scattered near it and in the lens, which
// rain scatters more, not less. On the real night clip of a white street lamp, wet ground, darken
// and fog turned the clipped core (1.0) into a grey 0.945 and took 19 % off its glow: the lamp
// looked switched down. The grading stages (wet ground, darken, blur, fog) leave the lamps and
// glows that stages/plate_lights.h finds in each frame as the plate holds them.
#include <vector>

#include "image/image.h"
#include "pipeline/stage.h"

namespace pluvia {

// Decides once per clip (ClipContext::nightPlate) whether its still is a night plate
// (isNightPlate), in a grading stage's prepare(): the still is made there, before the frames.
// Without a clip to make a still of (a stage run alone over one image), not.
void findNightPlate(ClipContext& clip);

// How much of each pixel of `frame` a lamp of a night clip holds (lampShare of the frame), made
// once per frame for every grading stage (FrameContext::lampShare); empty on a clip that is not
// a night plate (or not yet decided) or where no pixel of the frame is a lamp.
const std::vector<float>& frameLampShare(const ClipContext& clip, FrameContext& frame);

// The pixels a lamp holds, as they were before a grading stage, put back after it:
// after + share (before - after).
class KeptLamps {
 public:
  KeptLamps(const Image& before, const std::vector<float>& share);
  void restore(Image& after) const;

 private:
  struct Kept {
    size_t pixel;
    float share;
    float rgb[3];
  };
  std::vector<Kept> kept_;
};

}  // namespace pluvia
