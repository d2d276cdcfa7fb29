#include "envmap/frame_environment.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "envmap/scene_albedo.h"
#include "envmap/unseen_fill.h"
#include "image/luminance.h"
#include "image/ops.h"
#include "image/resize.h"
#include "optics/fresnel.h"

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
// A blue sky seen in the plate (blue its brightest channel, red its darkest), at least this
// saturated ((max - min) / max of its mean linear RGB) over at least kMinClearSkyFraction of
// the frame, is a clear sky: rain falls from it only in a passing shower, the sun lights the
// scene, and the plate has measured the sky itself, give or take its blue's clip (a clear sky is
// about as bright as the sunlit scene, not the several times an overcast sky lighting that scene
// would need). Lund's deep blue sky: 0.78; Sceaux Castle's pale one, its blue at the clip: 0.31.
// An overcast or hazy sky is grey (NTURain's: 0.14); a few bright bricks taken for sky are red.
constexpr double kClearSkySaturation = 0.25;
constexpr double kMinClearSkyFraction = 0.05;

// What the frame shows of its sky, and the scene's luminance under it.
struct PlateSkySample {
  double pixels = 0.0;
  std::array<double, 3> meanRgb{0, 0, 0};
  double meanElevationDeg = 0.0;  // of the sky pixels, 0 at least
  double sceneLuminance = 0.0;    // mean of the other pixels (all of them without sky)
};

PlateSkySample sampleSky(const Image& frame, const Camera& camera,
                         const std::vector<uint8_t>& sky) {
  PlateSkySample sample;
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

// The overcast sky assumed above a day plate: zenith the brighter of the plate's own sky's (the
// CIE profile through its mean at the mean elevation it is seen at) and the scene's
// (sceneZenith), tinted as the plate's sky. Under a clear sky the plate's own, as it shows it.
struct DaySky {
  double zenith = 0.0;
  // What lights the ground below the frame, and its colour at unit luminance: under a clear sky
  // the scene's zenith (sceneZenith) in white, its sun's light; else the sky's.
  double groundZenith = 0.0;
  std::array<double, 3> groundTint{1.0, 1.0, 1.0};
  bool clear = false;
  std::array<double, 3> tint{1.0, 1.0, 1.0};  // the sky's colour at unit luminance
  // What the plate's own sky is multiplied by to lie on that sky: over 1 where the plate clips or
  // compresses it (a display-referred sky darker than the sky that lights the scene), else 1.
  double plateSkyGain = 1.0;
  bool fromPlate = false;
  // The sky at elevation e (cos theta = sin e).
  std::array<float, 3> at(double elevationDeg) const {
    const double l =
        zenith * (1.0 + 2.0 * std::sin(std::max(0.0, elevationDeg) * M_PI / 180.0)) / 3.0;
    return {float(l * tint[0]), float(l * tint[1]), float(l * tint[2])};
  }
};

DaySky daySky(const PlateSkySample& seen, double skyShare, double sceneZenith) {
  DaySky sky;
  sky.zenith = sky.groundZenith = sceneZenith;
  if (skyShare < kMinSkyFraction) return sky;
  const double luminance = rec709Luminance(seen.meanRgb);
  for (size_t c = 0; c < 3; ++c) sky.tint[c] = seen.meanRgb[c] / std::max(1e-6, luminance);
  const double throughPlate =
      3.0 * luminance / (1.0 + 2.0 * std::sin(seen.meanElevationDeg * M_PI / 180.0));
  const std::array<double, 3>& rgb = seen.meanRgb;
  const bool blue = rgb[2] >= rgb[1] && rgb[1] >= rgb[0] && rgb[2] > 0.0;
  if (blue && 1.0 - rgb[0] / rgb[2] >= kClearSkySaturation && skyShare >= kMinClearSkyFraction) {
    sky.zenith = throughPlate;
    sky.clear = sky.fromPlate = true;
    return sky;
  }
  sky.zenith = sky.groundZenith = std::max(sceneZenith, throughPlate);
  sky.groundTint = sky.tint;
  sky.fromPlate = sky.zenith > sceneZenith;
  sky.plateSkyGain = throughPlate > 0.0 ? sky.zenith / throughPlate : 1.0;
  return sky;
}

// The plate's own sky pixels (`skyShare`: the share of each sample that is sky) brought onto the
// sky assumed above the frame: a clipped sky of 1.0 seen 15 deg up under a sky that lights the
// scene at Lz 8 is really about 4, and a drop refracts that, not the clip. Their structure (the
// clouds' gradient) is kept; the map then has no step at the frame's top edge.
void liftPlateSky(cv::Mat& small, const cv::Mat& skyShare, double gain) {
  if (gain <= 1.0 || skyShare.empty()) return;
  for (int y = 0; y < small.rows; ++y) {
    cv::Vec3f* row = small.ptr<cv::Vec3f>(y);
    const float* share = skyShare.ptr<float>(y);
    for (int x = 0; x < small.cols; ++x) row[x] *= float(1.0 + share[x] * (gain - 1.0));
  }
}

// The ground below the frame on a day plate (rows after `last`, the frame's lowest, below the
// horizon): level ground of the metered albedo under the assumed overcast sky, which it sees a
// share kSkyViewFactor of (irradiance 7 pi Lz / 9 from a whole CIE overcast sky), wet: its water
// film reflects what stands at the mirrored elevation (the profile above the horizon) with water's
// Fresnel reflectance, which is what a drop sees of the ground near the horizon (over 0.2 within
// 15 deg of it). The frame's lowest row (what stands there: a wall, a hedge) fades into it in log
// space over the angle the panorama's unseen ground takes (ModelFillSettings::obstacleBlendDeg).
void wetGround(std::vector<std::array<float, 3>>& profile, int last, const DaySky& sky) {
  constexpr double kWaterIndex = 1.333;
  const double blendDeg = ModelFillSettings{}.obstacleBlendDeg;
  const int mapHeight = int(profile.size());
  const auto elevationOf = [&](int r) { return 90.0 - 180.0 * (r + 0.5) / mapHeight; };
  const double irradianceOverPi = kSkyViewFactor * 7.0 / 9.0 * sky.groundZenith;
  const auto model = [&](int r) {
    const double e = elevationOf(r);
    const double reflectance =
        optics::fresnelReflectance(std::sin(std::abs(e) * M_PI / 180.0), kWaterIndex);
    const std::array<float, 3>& mirrored = profile[size_t(mapHeight - 1 - r)];
    std::array<double, 3> rgb{};
    for (size_t c = 0; c < 3; ++c)
      rgb[c] = (1.0 - reflectance) * kMeteredSceneAlbedo * irradianceOverPi * sky.groundTint[c] +
               reflectance * mirrored[c];
    return rgb;
  };
  const double lastElevation = elevationOf(last);
  const int anchor = std::max(last, mapHeight / 2);  // a frame above the horizon: from there
  const std::array<float, 3> seen = profile[size_t(anchor)];
  for (int r = anchor + 1; r < mapHeight; ++r) {
    const double fade =
        std::clamp(1.0 - (std::min(lastElevation, 0.0) - elevationOf(r)) / blendDeg, 0.0, 1.0);
    const std::array<double, 3> ground = model(r);
    for (size_t c = 0; c < 3; ++c)
      profile[size_t(r)][c] = float(std::pow(std::max(1e-6, double(seen[c])), fade) *
                                    std::pow(std::max(1e-6, ground[c]), 1.0 - fade));
  }
}

}  // namespace

FrameEnvironment frameEnvironment(const Image& frame, const Camera& camera,
                                  const std::vector<uint8_t>& sky, bool nightPlate,
                                  int widthTexels) {
  FrameEnvironment result;
  const int mapWidth = widthTexels, mapHeight = widthTexels / 2;

  // The sky above the frame. Rain falls from an overcast sky, whose radiance grows from the
  // horizon to the zenith as (1 + 2 sin e) (CIE overcast, Huang et al.'s L(theta) = Lz (1 + 2 cos
  // theta) / 3): the plate shows at most a band of it near the horizon, and a display-referred
  // plate clips it (and a camera's highlight knee compresses it). So the sky is the brighter of
  // two estimates: the profile through the frame's own sky at the mean elevation it is seen at,
  // and the sky that lights the scene as brightly as the frame shows it: an upright surface of
  // albedo a under it, seeing a share v of it, has radiance a E / pi with E = v kUprightIlluminance
  // Lz, so Lz = pi (the scene's mean luminance) / (a v kUprightIlluminance), about 34 times the
  // scene's mean (a = 0.125, envmap/scene_albedo.h; v = 2/3).
  const PlateSkySample seen = sampleSky(frame, camera, sky);
  const double pixels = double(camera.width) * camera.height;
  const double skyShare = seen.pixels / pixels;
  const bool framedSky = skyShare >= kMinSkyFraction;
  const double sceneZenith =
      M_PI * seen.sceneLuminance / (kMeteredSceneAlbedo * kSkyViewFactor * kUprightIlluminance);
  const DaySky day = daySky(seen, skyShare, sceneZenith);

  const double scale = std::min(1.0, double(kSampleWidthPx) / std::max(1, camera.width));
  cv::Mat rgb = rgbMat(frame), small;
  cv::resize(rgb, small, scaledSize(rgb.cols, rgb.rows, scale), 0, 0, cv::INTER_AREA);
  if (!nightPlate && framedSky) {
    cv::Mat share;
    cv::Mat(camera.height, camera.width, CV_8UC1, const_cast<uint8_t*>(sky.data()))
        .convertTo(share, CV_32F);  // 1 where sky
    cv::resize(share, share, small.size(), 0, 0, cv::INTER_AREA);
    liftPlateSky(small, share, day.plateSkyGain);
  }
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
    for (int r = 0; r < std::min(first, mapHeight); ++r) {
      const double elevation = 90.0 - 180.0 * (r + 0.5) / mapHeight;
      if (elevation > 0.0) profile[size_t(r)] = day.at(elevation);
    }
    result.zenithLuminance = float(day.zenith);
    result.skyFromPlate = day.fromPlate;
    result.clearSky = day.clear;
    // The airlight (the fog's colour): a long path toward the horizon looks as the plate shows
    // its own sky there (as recorded, clip and all: the fog is composited over the plate), where
    // it shows one.
    result.horizonRgb = framedSky
                            ? std::array<float, 3>{float(seen.meanRgb[0]), float(seen.meanRgb[1]),
                                                   float(seen.meanRgb[2])}
                            : day.at(0.0);
    wetGround(profile, last, day);
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
