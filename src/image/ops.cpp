#include "image/ops.h"

#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace pluvia::ops {

void darken(Image& image, float amount, float darkening) {
  if (amount == 0.0f) return;
  const float scale = 1.0f - amount * darkening;
  for (size_t i = 0; i < image.pixelCount(); ++i) {
    float* p = image.rgba.data() + i * 4;
    const float y = luminance(p);
    for (int c = 0; c < 3; ++c) p[c] = ((1.0f - amount) * p[c] + amount * y) * scale;
  }
}

void gaussianBlur(Image& image, float sigmaPx) {
  if (sigmaPx <= 0.0f || image.empty()) return;
  cv::Mat rgba = image.rgbaMat();
  cv::Mat blurred;
  // Kernel of +-4 sigma; BORDER_REFLECT keeps the weights summing to one at the edges.
  const int radius = std::max(1, static_cast<int>(std::ceil(4.0f * sigmaPx)));
  cv::GaussianBlur(rgba, blurred, cv::Size(2 * radius + 1, 2 * radius + 1), sigmaPx, sigmaPx, cv::BORDER_REFLECT);
  // Alpha is left as it was.
  const int fromTo[] = {0, 0, 1, 1, 2, 2};
  cv::mixChannels(&blurred, 1, &rgba, 1, fromTo, 3);
}

void fog(Image& image, float densityPerMeter, const std::array<float, 3>& fogRgb,
         float maxDepthMeters) {
  if (densityPerMeter == 0.0f) return;
  const std::vector<float>& depth = image.plane("depth");
  for (size_t i = 0; i < image.pixelCount(); ++i) {
    if (!(depth[i] < std::numeric_limits<float>::infinity())) continue;  // sky: its own airlight
    const float alpha = 1.0f - std::exp(-densityPerMeter * std::min(depth[i], maxDepthMeters));
    float* p = image.rgba.data() + i * 4;
    for (int c = 0; c < 3; ++c) p[c] = alpha * fogRgb[c] + (1.0f - alpha) * p[c];
  }
}

size_t replaceNonFinite(Image& image) {
  size_t replaced = 0;
  for (size_t i = 0; i < image.pixelCount(); ++i) {
    float* p = image.rgba.data() + i * 4;
    for (int c = 0; c < 4; ++c) {
      if (!std::isfinite(p[c])) {
        p[c] = c == 3 ? 1.0f : 0.0f;
        ++replaced;
      }
    }
  }
  return replaced;
}

}  // namespace pluvia::ops
