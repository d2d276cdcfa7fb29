#include "image/resize.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace pluvia {

cv::Size scaledSize(int width, int height, double scale) {
  auto side = [scale](int pixels) { return std::max(1, int(std::lround(pixels * scale))); };
  return {side(width), side(height)};
}

Image resizeArea(const Image& image, cv::Size size) {
  // A read-only view of the source: cv::resize never writes its input.
  const cv::Mat source(image.height, image.width, CV_32FC4, const_cast<float*>(image.rgba.data()));
  Image resized(size.width, size.height);
  cv::Mat target = resized.rgbaMat();
  cv::resize(source, target, size, 0, 0, cv::INTER_AREA);
  return resized;
}

}  // namespace pluvia
