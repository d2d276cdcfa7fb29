#include "stages/clip_median.h"

#include <algorithm>

namespace pluvia {

Image medianOfFrames(ClipContext& clip, const std::vector<int64_t>& frames, int maxFrames) {
  const int count = std::max(1, std::min<int>(maxFrames, int(frames.size())));
  std::vector<Image> images;
  for (int s = 0; s < count; ++s)
    images.push_back(clip.readWorking(frames[frames.size() * size_t(s) / size_t(count)]));
  Image median = images.front();
  if (count < 3) return median;
  std::vector<float> values(static_cast<size_t>(count));
  for (size_t i = 0; i < median.rgba.size(); ++i) {
    for (int s = 0; s < count; ++s) values[size_t(s)] = images[size_t(s)].rgba[i];
    std::nth_element(values.begin(), values.begin() + count / 2, values.end());
    median.rgba[i] = values[size_t(count / 2)];
  }
  return median;
}

}  // namespace pluvia
