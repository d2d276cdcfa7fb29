#include "envmap/frame_environment.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace pluvia::envmap {
namespace {

// The frame is sampled at about this width: the map is 128 texels around, so the frame's
// 36-60 deg cover 13-21 of them.
constexpr int kSampleWidthPx = 192;
// The mean albedo of what a plate shows (grass, asphalt, walls, foliage: 0.1-0.4).
constexpr double kSceneAlbedo = 0.25;

// The unit direction's elevation row in a map of `height` rows.
int rowOf(double y, int height) {
  const double v = std::acos(std::clamp(y, -1.0, 1.0)) / M_PI;
  return std::clamp(int(v * height), 0, height - 1);
}

}  // namespace

EquirectMap frameEnvironment(const Image& frame, const Camera& camera, int widthTexels) {
  const int mapWidth = widthTexels, mapHeight = widthTexels / 2;
  const double scale = std::min(1.0, double(kSampleWidthPx) / std::max(1, camera.width));
  cv::Mat rgb = rgbMat(frame), small;
  cv::resize(rgb, small, cv::Size(), scale, scale, cv::INTER_AREA);
  Camera view = camera;  // the same view at the sample size
  view.width = small.cols;
  view.height = small.rows;
  view.focalPx *= double(small.cols) / camera.width;
  view.cx *= double(small.cols) / camera.width;
  view.cy *= double(small.rows) / camera.height;

  // The elevation profile: the frame's mean per map row.
  std::vector<std::array<double, 3>> sum(size_t(mapHeight), {0, 0, 0});
  std::vector<double> count(size_t(mapHeight), 0.0);
  for (int y = 0; y < small.rows; ++y) {
    const cv::Vec3f* row = small.ptr<cv::Vec3f>(y);
    for (int x = 0; x < small.cols; ++x) {
      const Eigen::Vector3d d =
          (view.worldFromCamera * view.rayCamera(x + 0.5, y + 0.5)).normalized();
      const size_t r = size_t(rowOf(d.y(), mapHeight));
      for (int c = 0; c < 3; ++c) sum[r][size_t(c)] += row[x][c];
      count[r] += 1.0;
    }
  }
  // Rows the frame never reaches take the nearest row it does (the top rows above, the bottom
  // ones below).
  std::vector<std::array<float, 3>> profile(static_cast<size_t>(mapHeight));
  int first = mapHeight, last = -1;
  for (int r = 0; r < mapHeight; ++r)
    if (count[size_t(r)] > 0) first = std::min(first, r), last = std::max(last, r);
  for (int r = 0; r < mapHeight; ++r) {
    int from = std::clamp(r, first, last);
    while (count[size_t(from)] == 0) ++from;  // a gap inside the covered rows
    for (int c = 0; c < 3; ++c)
      profile[size_t(r)][size_t(c)] = float(sum[size_t(from)][size_t(c)] / count[size_t(from)]);
  }

  // The sky above the frame is at least as bright as the overcast sky that would light the
  // scene this brightly: under a uniform sky of radiance L a surface of albedo a has radiance
  // a L, so L = the frame's mean luminance over a typical albedo. (A frame that shows a bright
  // sky keeps its own, brighter, top rows.)
  double luminanceSum = 0.0;
  for (int y = 0; y < small.rows; ++y)
    for (int x = 0; x < small.cols; ++x) {
      const cv::Vec3f& v = small.at<cv::Vec3f>(y, x);
      luminanceSum += 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2];
    }
  const float skyLuminance = float(luminanceSum / (double(small.rows) * small.cols) / kSceneAlbedo);
  for (int r = 0; r < mapHeight; ++r) {
    const double elevation = 90.0 - 180.0 * (r + 0.5) / mapHeight;
    if (elevation <= 0.0 || r >= first) continue;  // the frame's own rows and the ground
    std::array<float, 3>& rgb = profile[size_t(r)];
    const float luminance = 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2];
    if (luminance >= skyLuminance) continue;
    // Rows nearly as bright keep their colour (a blue sky stays blue); darker ones are not the
    // sky (a wall's brick, foliage) and take a neutral grey.
    const float scale = skyLuminance / std::max(luminance, 1e-6f);
    for (int c = 0; c < 3; ++c)
      rgb[size_t(c)] = scale <= 2.0f ? rgb[size_t(c)] * scale : skyLuminance;
  }

  EquirectMap map(mapWidth, mapHeight);
  const Eigen::Matrix3d cameraFromWorld = view.worldFromCamera.transpose();
  for (int y = 0; y < mapHeight; ++y) {
    for (int x = 0; x < mapWidth; ++x) {
      const auto d = equirectTexelDirection(mapWidth, mapHeight, x, y);
      const Eigen::Vector3d c = cameraFromWorld * Eigen::Vector3d(d[0], d[1], d[2]);
      float* out = map.texel(x, y);
      const std::array<float, 3>& fill = profile[size_t(y)];
      std::copy(fill.begin(), fill.end(), out);
      if (c.z() >= -1e-6) continue;  // behind the camera
      const double px = view.cx + view.focalPx * c.x() / -c.z();
      const double py = view.cy - view.focalPx * c.y() / -c.z();
      if (px < 0 || py < 0 || px >= small.cols || py >= small.rows) continue;
      cv::Mat texel;
      cv::getRectSubPix(small, cv::Size(1, 1), cv::Point2f(float(px - 0.5), float(py - 0.5)),
                        texel);
      const cv::Vec3f v = texel.at<cv::Vec3f>(0, 0);
      for (int ch = 0; ch < 3; ++ch) out[ch] = v[ch];
    }
  }
  return map;
}

}  // namespace pluvia::envmap
