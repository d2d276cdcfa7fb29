#include "image/image.h"

#include <opencv2/imgproc.hpp>

#include <cmath>

namespace pluvia {

Image::Image(int w, int h) : width(w), height(h), rgba(static_cast<size_t>(w) * h * 4, 0.0f) {
  for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 1.0f;
}

std::vector<float>& Image::plane(const std::string& name) {
  auto& p = planes[name];
  if (p.size() != pixelCount()) p.assign(pixelCount(), 0.0f);
  return p;
}

const std::vector<float>* Image::findPlane(const std::string& name) const {
  auto it = planes.find(name);
  return it == planes.end() ? nullptr : &it->second;
}

cv::Mat Image::rgbaMat() {
  return cv::Mat(height, width, CV_32FC4, rgba.data());
}

cv::Mat rgbMat(const Image& image) {
  const cv::Mat rgba(image.height, image.width, CV_32FC4, const_cast<float*>(image.rgba.data()));
  cv::Mat rgb;
  cv::cvtColor(rgba, rgb, cv::COLOR_RGBA2RGB);
  return rgb;
}

Image imageFromMat(const cv::Mat& rgbOrGray) {
  cv::Mat rgb = rgbOrGray;
  if (rgbOrGray.channels() == 1) cv::cvtColor(rgbOrGray, rgb, cv::COLOR_GRAY2RGB);
  Image image(rgb.cols, rgb.rows);
  cv::cvtColor(rgb, image.rgbaMat(), cv::COLOR_RGB2RGBA);
  return image;
}

std::array<double, 3> meanRgb(const Image& image) {
  std::array<double, 3> sum{0, 0, 0};
  size_t count = 0;
  for (size_t i = 0; i < image.pixelCount(); ++i) {
    const float* p = image.rgba.data() + i * 4;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    for (int c = 0; c < 3; ++c) sum[c] += p[c];
    ++count;
  }
  if (count == 0) return {0, 0, 0};
  for (auto& s : sum) s /= static_cast<double>(count);
  return sum;
}

}  // namespace pluvia
