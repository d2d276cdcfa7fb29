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
// The mean albedo of what a plate shows (grass, asphalt, walls, foliage: 0.1-0.4): the 18 % grey
// a light meter assumes.
constexpr double kSceneAlbedo = 0.18;
// A frame whose sky covers less than this is taken to show none.
constexpr double kMinSkyFraction = 0.01;

// The unit direction's elevation row in a map of `height` rows.
int rowOf(double y, int height) {
  const double v = std::acos(std::clamp(y, -1.0, 1.0)) / M_PI;
  return std::clamp(int(v * height), 0, height - 1);
}

}  // namespace

FrameEnvironment frameEnvironment(const Image& frame, const Camera& camera,
                                  const std::vector<uint8_t>& sky, int widthTexels) {
  FrameEnvironment result;
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

  // The sky above the frame: the frame's own sky where it shows one; else the CIE overcast sky
  // (Huang et al.'s, L(theta) = Lz (1 + 2 cos theta) / 3) that would light the scene as
  // brightly as the frame shows it: its illuminance is E = 7 pi Lz / 9, and a surface of albedo
  // a lit by it has radiance a E / pi, so Lz = 9 / 7 * (the frame's mean luminance) / a.
  std::array<double, 3> skySum{0, 0, 0};
  double skyCount = 0.0, luminanceSum = 0.0;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const float* p = frame.rgba.data() + (size_t(y) * camera.width + x) * 4;
      luminanceSum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
      if (sky.empty() || !sky[size_t(y) * camera.width + x]) continue;
      for (int c = 0; c < 3; ++c) skySum[size_t(c)] += p[c];
      skyCount += 1.0;
    }
  const double pixels = double(camera.width) * camera.height;
  const bool framedSky = skyCount >= kMinSkyFraction * pixels;
  const double zenith = 9.0 / 7.0 * luminanceSum / pixels / kSceneAlbedo;
  // The sky at elevation e (cos theta = sin e).
  const auto skyAt = [&](double elevationDeg) -> std::array<float, 3> {
    if (framedSky)
      return {float(skySum[0] / skyCount), float(skySum[1] / skyCount),
              float(skySum[2] / skyCount)};
    const float l = float(zenith * (1.0 + 2.0 * std::sin(elevationDeg * M_PI / 180.0)) / 3.0);
    return {l, l, l};
  };
  for (int r = 0; r < std::min(first, mapHeight); ++r) {
    const double elevation = 90.0 - 180.0 * (r + 0.5) / mapHeight;
    if (elevation > 0.0) profile[size_t(r)] = skyAt(elevation);
  }
  result.horizonRgb = skyAt(0.0);

  EquirectMap& map = result.radiance;
  map = EquirectMap(mapWidth, mapHeight);
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
  return result;
}

}  // namespace pluvia::envmap
