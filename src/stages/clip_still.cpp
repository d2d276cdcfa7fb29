#include "stages/clip_still.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "image/resize.h"
#include "sfm/sparse_densify.h"

namespace pluvia {
namespace {

constexpr int kStillFrames = 5;
// The sky is found at this longest side, whatever the plate's size: the texture test and the
// seed and speck sizes are in pixels, so a proxy render and the full one find the same sky,
// and a 4K plate does not cost seconds for a mask that needs no such detail.
constexpr int kSkySidePx = 480;

}  // namespace

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

const Image& clipStill(ClipContext& clip) {
  if (!clip.still) clip.still = medianOfFrames(clip, clip.clip->frames, kStillFrames);
  return *clip.still;
}

const std::vector<uint8_t>& clipSky(ClipContext& clip, const Camera& camera) {
  if (clip.stillSky) return *clip.stillSky;
  const Image& still = clipStill(clip);
  const double scale = double(kSkySidePx) / std::max(still.width, still.height);
  cv::Mat small, bgr;
  cv::resize(rgbMat(still), small, scaledSize(still.width, still.height, scale), 0, 0,
             scale < 1.0 ? cv::INTER_AREA : cv::INTER_LINEAR);
  cv::cvtColor(small, bgr, cv::COLOR_RGB2BGR);
  sfm::DensifyOptions options;
  options.groundCamera = camera;
  cv::Mat skySmall = sfm::estimateSkyMask(bgr, options), sky;
  cv::resize(skySmall, sky, cv::Size(still.width, still.height), 0, 0, cv::INTER_NEAREST);
  std::vector<uint8_t> mask(size_t(still.width) * still.height);
  for (int y = 0; y < still.height; ++y)
    for (int x = 0; x < still.width; ++x)
      mask[size_t(y) * still.width + x] = sky.at<uchar>(y, x) ? 1 : 0;
  clip.stillSky = std::move(mask);
  return *clip.stillSky;
}

}  // namespace pluvia
