#include "envmap/frame_environment.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "envmap/scene_albedo.h"
#include "image/luminance.h"
#include "image/ops.h"
#include "image/resize.h"

namespace pluvia::envmap {
namespace {

// The frame is sampled at about this width: the map is 128 texels around, so the frame's
// 36-60 deg cover 13-21 of them.
constexpr int kSampleWidthPx = 192;
// What a plate shows is mostly upright (walls, trees, people, cars). Under the CIE overcast sky an
// upright surface receives (2/3)(pi/4 + 2/3) Lz from the sky and, from ground of the same albedo,
// half of a level surface's 7 pi / 9 Lz times that albedo: its illuminance per unit Lz.
const double kUprightIlluminance =
    2.0 / 3.0 * (M_PI / 4.0 + 2.0 / 3.0) + kMeteredSceneAlbedo * 7.0 * M_PI / 9.0 / 2.0;
// What a plate shows stands among other things (the street's far side, trees, eaves, the
// camera's own surroundings) that hide part of the sky from it: sky view factors in streets
// and gardens run 0.4-0.8 of an open site's. A drop in the open air between them sees more of
// it; pluvia takes the surfaces' share as 2/3.
constexpr double kSkyViewFactor = 2.0 / 3.0;
// A frame whose sky covers less than this is taken to show none.
constexpr double kMinSkyFraction = 0.01;

// What the frame shows of its sky, and the scene's luminance under it.
struct SkySample {
  double pixels = 0.0;
  std::array<double, 3> meanRgb{0, 0, 0};
  double meanElevationDeg = 0.0;  // of the sky pixels, 0 at least
  double sceneLuminance = 0.0;    // mean of the other pixels (all of them without sky)
};

SkySample sampleSky(const Image& frame, const Camera& camera, const std::vector<uint8_t>& sky) {
  SkySample sample;
  double sceneSum = 0.0, scenePixels = 0.0, elevationSum = 0.0;
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const float* p = frame.rgba.data() + (size_t(y) * camera.width + x) * 4;
      if (sky.empty() || !sky[size_t(y) * camera.width + x]) {
        sceneSum += rec709Luminance(p);
        scenePixels += 1.0;
        continue;
      }
      for (int c = 0; c < 3; ++c) sample.meanRgb[size_t(c)] += p[c];
      const Eigen::Vector3d d =
          (camera.worldFromCamera * camera.rayCamera(x + 0.5, y + 0.5)).normalized();
      elevationSum += std::max(0.0, std::asin(std::clamp(d.y(), -1.0, 1.0)) * 180.0 / M_PI);
      sample.pixels += 1.0;
    }
  if (sample.pixels > 0.0) {
    for (double& v : sample.meanRgb) v /= sample.pixels;
    sample.meanElevationDeg = elevationSum / sample.pixels;
  }
  sample.sceneLuminance = scenePixels > 0.0 ? sceneSum / scenePixels : 0.0;
  return sample;
}

// The unit direction's elevation row in a map of `height` rows.
int rowOf(double y, int height) {
  const double v = std::acos(std::clamp(y, -1.0, 1.0)) / M_PI;
  return std::clamp(int(v * height), 0, height - 1);
}

// The day sky above the frame (rows before `first`): the CIE overcast profile of zenith the
// brighter of the plate's own sky's and the scene's (sceneZenith), tinted as the plate's sky.
void daySky(FrameEnvironment& result, std::vector<std::array<float, 3>>& profile, int first,
            const SkySample& seen, bool framedSky, double sceneZenith) {
  const int mapHeight = int(profile.size());
  double zenith = sceneZenith;
  std::array<double, 3> tint{1.0, 1.0, 1.0};  // the sky's colour at unit luminance
  if (framedSky) {
    const double luminance = rec709Luminance(seen.meanRgb);
    for (int c = 0; c < 3; ++c)
      tint[size_t(c)] = seen.meanRgb[size_t(c)] / std::max(1e-6, luminance);
    const double throughPlate =
        3.0 * luminance / (1.0 + 2.0 * std::sin(seen.meanElevationDeg * M_PI / 180.0));
    zenith = std::max(sceneZenith, throughPlate);
  }
  result.zenithLuminance = float(zenith);
  result.skyFromPlate = framedSky && zenith > sceneZenith;
  // The sky at elevation e (cos theta = sin e).
  const auto skyAt = [&](double elevationDeg) -> std::array<float, 3> {
    const double l =
        zenith * (1.0 + 2.0 * std::sin(std::max(0.0, elevationDeg) * M_PI / 180.0)) / 3.0;
    return {float(l * tint[0]), float(l * tint[1]), float(l * tint[2])};
  };
  for (int r = 0; r < std::min(first, mapHeight); ++r) {
    const double elevation = 90.0 - 180.0 * (r + 0.5) / mapHeight;
    if (elevation > 0.0) profile[size_t(r)] = skyAt(elevation);
  }
  // The airlight (the fog's colour): a long path toward the horizon looks as the plate shows its
  // own sky there, where it shows one.
  result.horizonRgb = framedSky
                          ? std::array<float, 3>{float(seen.meanRgb[0]), float(seen.meanRgb[1]),
                                                 float(seen.meanRgb[2])}
                          : skyAt(0.0);
}

}  // namespace

FrameEnvironment frameEnvironment(const Image& frame, const Camera& camera,
                                  const std::vector<uint8_t>& sky, bool nightPlate,
                                  int widthTexels) {
  FrameEnvironment result;
  const int mapWidth = widthTexels, mapHeight = widthTexels / 2;
  const double scale = std::min(1.0, double(kSampleWidthPx) / std::max(1, camera.width));
  cv::Mat rgb = rgbMat(frame), small;
  cv::resize(rgb, small, scaledSize(rgb.cols, rgb.rows, scale), 0, 0, cv::INTER_AREA);
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

  // The sky above the frame. Rain falls from an overcast sky, whose radiance grows from the
  // horizon to the zenith as (1 + 2 sin e) (CIE overcast, Huang et al.'s L(theta) = Lz (1 + 2 cos
  // theta) / 3): the plate shows at most a band of it near the horizon, and a display-referred
  // plate clips it (and a camera's highlight knee compresses it). So the sky is the brighter of
  // two estimates: the profile through the frame's own sky at the mean elevation it is seen at,
  // and the sky that lights the scene as brightly as the frame shows it: an upright surface of
  // albedo a under it, seeing a share v of it, has radiance a E / pi with E = v kUprightIlluminance
  // Lz, so Lz = pi (the scene's mean luminance) / (a v kUprightIlluminance), about 34 times the
  // scene's mean (a = 0.125, envmap/scene_albedo.h; v = 2/3).
  const SkySample seen = sampleSky(frame, camera, sky);
  const double pixels = double(camera.width) * camera.height;
  const bool framedSky = seen.pixels >= kMinSkyFraction * pixels;
  const double sceneZenith =
      M_PI * seen.sceneLuminance / (kMeteredSceneAlbedo * kSkyViewFactor * kUprightIlluminance);
  if (nightPlate) {
    // At night the scene is lit by its lamps, not by the sky: the sky is what the plate shows of
    // it, or without sky in view the frame's top rows carried up (the profile already).
    if (framedSky)
      for (int r = 0; r < std::min(first, mapHeight); ++r)
        if (90.0 - 180.0 * (r + 0.5) / mapHeight > 0.0)
          profile[size_t(r)] = {float(seen.meanRgb[0]), float(seen.meanRgb[1]),
                                float(seen.meanRgb[2])};
    result.horizonRgb = profile[size_t(std::clamp(mapHeight / 2 - 1, 0, mapHeight - 1))];
    result.zenithLuminance = ops::luminance(profile[0].data());
    result.skyFromPlate = true;
  } else {
    daySky(result, profile, first, seen, framedSky, sceneZenith);
  }

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
