#pragma once
// The sky of each frame of a moving camera's clip, for the default depth's guess when the clip's
// still stands for no frame (stages/depth_stage.cpp): found in the frame (clip_still.h), then
// voted with the frames just before and after it, each shifted onto it by the phase correlation
// of their greys: a pixel is sky where at least two of the three say so. A patch at the sky
// finder's thresholds (a pale block under a grey sky, a wall catching the light) then does not
// switch between sky and backdrop from one frame to the next, and the depth AOV and the fog with
// it do not flicker. At the clip's ends, and beside a neighbour that cannot be placed (a weak
// correlation peak: a cut, a whip pan), the frame keeps its own sky. Each frame's sky is a
// function of its picture alone, so the chunks of a farm render vote alike.
#include <cstdint>
#include <functional>
#include <map>
#include <vector>

#include "geometry/camera.h"
#include "pipeline/stage.h"
#include "stages/clip_still.h"

namespace pluvia {

class FrameSky {
 public:
  // `cameraAt`: the camera at a clip frame (the sky finder's horizon test).
  explicit FrameSky(std::function<Camera(double)> cameraAt) : cameraAt_(std::move(cameraAt)) {}

  // Frame `frame`'s voted sky at the image's size, 1 where sky; `image` is that frame as the
  // clip's readWorking gives it.
  std::vector<uint8_t> at(ClipContext& clip, int64_t frame, const Image& image);

 private:
  const SmallSky& smallAt(ClipContext& clip, int64_t frame, const Image* image);

  std::function<Camera(double)> cameraAt_;
  std::function<Image(int64_t)> neighbours_;  // a reader of its own (clip.openWorkingReader)
  std::map<int64_t, SmallSky> recent_;        // the last frames' (frames render in order)
};

}  // namespace pluvia
