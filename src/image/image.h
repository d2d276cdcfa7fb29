#pragma once
// Frames inside pluvia. Conventions, written once here and assumed by every image operation:
//  - pixels are 32-bit float RGBA, interleaved, row-major, row 0 at the top of the picture;
//  - colour is scene-linear in the working space (colour conversion happens only at read and
//    write, in color.h);
//  - alpha is straight (not premultiplied) and is 1 where the input had none;
//  - extra single-channel planes travel by name: "depth" is z-depth in metres along the
//    camera's optical axis (+infinity for sky), "matte" and "rain_alpha" are 0..1.
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace pluvia {

// The name of the z-depth plane (metres along the optical axis, +infinity for sky).
inline constexpr const char* kDepthPlane = "depth";
// The sky's depth as the render's depth AOV writes it: finite, so that a compositor's ZDefocus
// and filters work on it, and the largest half float, so that it stays finite when a tool
// converts the channel to half. depth.file reads it (and anything beyond) back as sky.
inline constexpr float kSkyDepthInAovMeters = 65504.0f;

struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> rgba;                           // width * height * 4
  std::map<std::string, std::vector<float>> planes;  // each width * height

  Image() = default;
  Image(int w, int h);  // RGBA zeros, alpha 1

  bool empty() const { return width <= 0 || height <= 0; }
  size_t pixelCount() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
  float* pixel(int x, int y) { return rgba.data() + (static_cast<size_t>(y) * width + x) * 4; }
  const float* pixel(int x, int y) const {
    return rgba.data() + (static_cast<size_t>(y) * width + x) * 4;
  }
  std::vector<float>& plane(const std::string& name);  // created (zeros) if absent
  const std::vector<float>* findPlane(const std::string& name) const;

  // A view sharing memory: CV_32FC4 over rgba.
  cv::Mat rgbaMat();
};

// R, G, B as a CV_32FC3 copy (channel order R, G, B kept; alpha and planes dropped).
cv::Mat rgbMat(const Image& image);
// An image from CV_32FC3 R, G, B, or from CV_32FC1 (the value in all three); alpha 1.
Image imageFromMat(const cv::Mat& rgbOrGray);

// Mean of R, G, B over all pixels (finite values only).
std::array<double, 3> meanRgb(const Image& image);

}  // namespace pluvia
