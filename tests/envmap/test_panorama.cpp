// Environment maps from footage (Wang et al. section 4.1): frames cut from known environments at
// known angles, placed by features, rendered back into an equirect map and compared.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "envmap/panorama.h"
#include "envmap/perspective_view.h"
#include "envmap/sky_model.h"
#include "lab/test_environment.h"
#include "optics/environment_file.h"
#include "test_support.h"

namespace pluvia::envmap {
namespace {

constexpr double kDeg = CV_PI / 180.0;

cv::Vec3d forwardOf(const CameraPose& pose) {
  return pose.cameraToWorld * cv::Vec3d(0, 0, -1);
}
double yawOf(const CameraPose& pose) {
  const cv::Vec3d f = forwardOf(pose);
  return std::atan2(f[0], -f[2]) / kDeg;
}
double wrapDeg(double a) {
  return std::remainder(a, 360.0);
}

// A textured environment ORB can hold on to: a graded sky and ground under a few hundred
// random discs and boxes of random colours (all below 0.85, so nothing clips at exposure 1).
EquirectMap texturedEnvironment(int width = 2048) {
  const int height = width / 2;
  cv::Mat img(height, width, CV_32FC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double t = 1.0 - double(y) / height;
      img.at<cv::Vec3f>(y, x) = cv::Vec3f(float(0.2 + 0.3 * t), float(0.25 + 0.3 * t), 0.45f);
    }
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> colour(0.04f, 0.85f);
  std::uniform_int_distribution<int> px(0, width - 1), py(height / 8, height * 7 / 8);
  std::uniform_int_distribution<int> size(4, width / 60);
  for (int i = 0; i < 1500; ++i) {
    const cv::Scalar c(colour(rng), colour(rng), colour(rng));
    const cv::Point p(px(rng), py(rng));
    const int r = size(rng), s = size(rng);
    for (const int shift : {-width, 0, width}) {  // wrapped, so the map is seamless at u = 0 / 1
      const cv::Point q = p + cv::Point(shift, 0);
      if (i % 2)
        cv::circle(img, q, r, c, cv::FILLED, cv::LINE_AA);
      else
        cv::rectangle(img, q, q + cv::Point(r, s), c, cv::FILLED);
    }
  }
  EquirectMap map(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c) map.texel(x, y)[c] = img.at<cv::Vec3f>(y, x)[c];
  return map;
}

std::vector<PanoramaFrame> cutFrames(const EquirectMap& env, const std::vector<double>& yaws,
                                     double pitch, double fov, int w, int h,
                                     const std::vector<double>& exposures) {
  std::vector<PanoramaFrame> frames;
  for (std::size_t k = 0; k < yaws.size(); ++k)
    frames.push_back(
        recordView(env, panPose(yaws[k], pitch, fov, w), w, h, exposures[k % exposures.size()])
            .frame);
  return frames;
}

Placement knownPlacement(const std::vector<double>& yaws, double pitch, double fov, int w) {
  Placement p;
  for (double yaw : yaws) p.poses.push_back(panPose(yaw, pitch, fov, w));
  p.fromFeatures = true;
  return p;
}

bool allFinite(const EquirectMap& map) {
  for (float v : map.rgb)
    if (!std::isfinite(v)) return false;
  return true;
}

// Mean relative error of the panorama against the environment (times `scale`) over the texels
// that are covered and not near anything bright.
double coveredRelativeError(const PanoramaResult& pano, const EquirectMap& env, double scale,
                            int* count = nullptr) {
  double sum = 0;
  int n = 0;
  const int w = pano.radiance.width, h = pano.radiance.height;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!pano.coverage.at<uchar>(y, x)) continue;
      const auto d = equirectTexelDirection(w, h, x, y);
      const auto ref = sampleEquirect(env, float(d[0]), float(d[1]), float(d[2]));
      const float* got = pano.radiance.texel(x, y);
      double r = 0, g = 0;
      bool bright = false;
      for (int c = 0; c < 3; ++c) {
        r += ref[c] * scale;
        g += got[c];
        if (ref[c] * scale > 0.95) bright = true;
      }
      if (bright) continue;
      sum += std::abs(g - r) / std::max(r, 0.05);
      ++n;
    }
  if (count) *count = n;
  return n ? sum / n : 1.0;
}

TEST(Panorama, RecordViewSamplesAlongThePixelRays) {
  // An environment whose colour encodes the direction: (d + 1) / 2 * 0.8.
  EquirectMap env(1024, 512);
  for (int y = 0; y < env.height; ++y)
    for (int x = 0; x < env.width; ++x) {
      const auto d = equirectTexelDirection(env.width, env.height, x, y);
      for (int c = 0; c < 3; ++c) env.texel(x, y)[c] = float((d[c] + 1.0) * 0.4);
    }
  const int w = 320, h = 180;
  const CameraPose pose = panPose(37.0, 12.0, 60.0, w);
  EXPECT_NEAR(pose.focalPx, 0.5 * w / std::tan(30.0 * kDeg), 1e-9);
  // Positive yaw turns right (toward +X), positive pitch up.
  const cv::Vec3d f = forwardOf(pose);
  EXPECT_NEAR(f[0], std::sin(37 * kDeg) * std::cos(12 * kDeg), 1e-12);
  EXPECT_NEAR(f[1], std::sin(12 * kDeg), 1e-12);
  EXPECT_NEAR(f[2], -std::cos(37 * kDeg) * std::cos(12 * kDeg), 1e-12);
  const RecordedFrame rec = recordView(env, pose, w, h, 1.0);
  double worst = 0;
  for (const cv::Point p : {cv::Point(0, 0), cv::Point(w - 1, 0), cv::Point(w / 2, h / 2),
                            cv::Point(17, h - 1), cv::Point(w - 1, h - 1)}) {
    cv::Vec3d ray((p.x + 0.5 - w / 2.0) / pose.focalPx, -(p.y + 0.5 - h / 2.0) / pose.focalPx,
                  -1.0);
    ray = pose.cameraToWorld * ray;
    ray /= cv::norm(ray);
    const cv::Vec3f got = rec.frame.linearRgb.at<cv::Vec3f>(p);
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(got[c] / 0.4 - 1.0 - ray[c]));
    EXPECT_EQ(rec.frame.saturated.at<uchar>(p), 0);
  }
  EXPECT_LT(worst, 0.03);  // 8-bit sRGB quantisation and bilinear lookup

  // Exposure: clipped pixels are flagged, their linear value is the clip.
  const RecordedFrame hot = recordView(env, pose, w, h, 4.0);
  EXPECT_GT(cv::countNonZero(hot.frame.saturated), 0);
  cv::Point maxAt;
  double maxVal;
  cv::minMaxLoc(hot.frame.linearRgb.reshape(1), nullptr, &maxVal);
  EXPECT_NEAR(maxVal, 1.0, 1e-6);
  EXPECT_EQ(hot.displayRgb8.type(), CV_8UC3);
}

TEST(Panorama, SyntheticPanRecoversYawFocalAndRadiance) {
  const EquirectMap env = texturedEnvironment();
  const std::vector<double> yaws = {0, 20, 40, 60, 80, 100, 120};
  const int w = 640, h = 360;
  const double fov = 60.0;
  const auto frames = cutFrames(env, yaws, 0.0, fov, w, h, {1.0});
  PlacementSettings settings;
  settings.horizontalFovDeg = 45.0;  // a seed only, deliberately off
  const Placement placement = placeFrames(frames, settings);
  ASSERT_TRUE(placement.fromFeatures) << placement.note;
  ASSERT_EQ(placement.poses.size(), yaws.size());
  const double trueFocal = panPose(0, 0, fov, w).focalPx;
  double worstYaw = 0, worstFocal = 0, worstPitch = 0;
  for (std::size_t k = 0; k < yaws.size(); ++k) {
    worstYaw = std::max(worstYaw, std::abs(wrapDeg(yawOf(placement.poses[k]) - yaws[k])));
    worstPitch = std::max(worstPitch, std::abs(std::asin(forwardOf(placement.poses[k])[1]) / kDeg));
    worstFocal = std::max(worstFocal, std::abs(placement.poses[k].focalPx / trueFocal - 1.0));
  }
  std::printf("synthetic pan: worst yaw error %.3f deg, pitch %.3f deg, focal %.2f %%\n", worstYaw,
              worstPitch, 100 * worstFocal);
  EXPECT_LT(worstYaw, 1.0);
  EXPECT_LT(worstPitch, 1.0);
  EXPECT_LT(worstFocal, 0.03);

  EquirectSettings es;
  es.width = 1024;
  const PanoramaResult pano = renderEquirect(frames, placement, es);
  ASSERT_EQ(pano.gains.size(), frames.size());
  for (float g : pano.gains) EXPECT_NEAR(g, 1.0, 0.03);
  int count = 0;
  const double err = coveredRelativeError(pano, env, 1.0, &count);
  std::printf("synthetic pan: covered %.3f of the sphere, mean relative error %.4f (%d texels)\n",
              pano.coveredFraction, err, count);
  EXPECT_LT(err, 0.05);
  EXPECT_GT(count, 1000);
  EXPECT_TRUE(allFinite(pano.radiance));
}

TEST(Panorama, PanWithBlankFramesIsPlacedByTheOthersAndInterpolated) {
  // A 75 deg pan in 11 frames of which two are blank (a featureless wall): the nine with
  // features place the pan, the blank ones turn between their neighbours.
  const EquirectMap env = texturedEnvironment();
  std::vector<double> yaws;
  for (int k = 0; k < 11; ++k) yaws.push_back(7.5 * k);
  const int w = 480, h = 270;
  auto frames = cutFrames(env, yaws, 0.0, 60.0, w, h, {1.0});
  for (int blank : {4, 5}) frames[size_t(blank)].linearRgb.setTo(cv::Scalar::all(0.3));
  PlacementSettings settings;
  settings.horizontalFovDeg = 60.0;
  const Placement placement = placeFrames(frames, settings);
  ASSERT_TRUE(placement.fromFeatures) << placement.note;
  EXPECT_EQ(placement.interpolated, (std::vector<int>{4, 5}));
  EXPECT_NE(placement.note.find("4, 5"), std::string::npos) << placement.note;
  for (size_t k = 0; k < yaws.size(); ++k)
    EXPECT_NEAR(wrapDeg(yawOf(placement.poses[k]) - yaws[k]), 0.0, 1.5) << "frame " << k;
}

// The panoramas of `env` seen by a level pan of eight 60-degree frames, filled by the sky model
// and by the nearest colour.
struct Fills {
  PanoramaResult model, nearest;
};
Fills levelPanFills(const EquirectMap& env) {
  const std::vector<double> yaws = {0, 45, 90, 135, 180, 225, 270, 315};
  const auto frames = cutFrames(env, yaws, 0.0, 60.0, 320, 180, {1.0});
  const Placement placement = knownPlacement(yaws, 0.0, 60.0, 320);
  EquirectSettings settings;
  settings.width = 256;
  settings.fill = UnseenFill::SkyModel;
  Fills fills{renderEquirect(frames, placement, settings), {}};
  settings.fill = UnseenFill::Nearest;
  fills.nearest = renderEquirect(frames, placement, settings);
  return fills;
}

TEST(Panorama, SkyModelFillRecoversAnOvercastZenithTheNearestFillCannot) {
  // A CIE overcast sky (Lz = 0.8) over a grey ground, seen only by a level pan around the
  // horizon: the model fitted to the seen sky gives the unseen zenith; the nearest colour
  // repeats the band's top.
  EquirectMap env(512, 256);
  for (int y = 0; y < env.height; ++y)
    for (int x = 0; x < env.width; ++x) {
      const double cosTheta = std::cos(CV_PI * (y + 0.5) / env.height);
      const float v = cosTheta > 0 ? float(0.8 * (1.0 + 2.0 * cosTheta) / 3.0) : 0.15f;
      for (int c = 0; c < 3; ++c) env.texel(x, y)[c] = v;
    }
  const auto [model, nearest] = levelPanFills(env);
  EXPECT_EQ(model.fillModel.rfind("cie overcast", 0), 0u) << model.fillModel;
  EXPECT_NEAR(sampleEquirect(model.radiance, 0, 1, 0)[1], 0.8, 0.03);
  EXPECT_NEAR(sampleEquirect(model.radiance, 0, -1, 0)[1], 0.15, 0.01);
  EXPECT_LT(sampleEquirect(nearest.radiance, 0, 1, 0)[1], 0.7);
  EXPECT_TRUE(allFinite(model.radiance));
}

TEST(Panorama, SkyModelFillIsAPreethamSkyWithoutASeamAtTheCoverage) {
  // A Preetham sky (T 3, sun 35° up) over a grey ground, seen by a level pan: the unseen zenith
  // within 10 % of the true sky (the nearest colour misses it by twice as much), and at the top
  // edge of the coverage the fill continues the seen colour.
  EquirectMap env(512, 256);
  const Vec3 sun = {std::cos(35 * kDeg) * std::sin(40 * kDeg), std::sin(35 * kDeg),
                    -std::cos(35 * kDeg) * std::cos(40 * kDeg)};
  for (int y = 0; y < env.height; ++y)
    for (int x = 0; x < env.width; ++x) {
      const auto d = equirectTexelDirection(env.width, env.height, x, y);
      const Vec3 sky = preethamRgb(3.0, sun, d);
      for (int c = 0; c < 3; ++c)
        env.texel(x, y)[c] = d[1] > 0 ? float(0.03 * sky[size_t(c)]) : 0.12f;
    }
  const auto [model, nearest] = levelPanFills(env);
  EXPECT_EQ(model.fillModel.rfind("preetham", 0), 0u) << model.fillModel;
  const auto truth = sampleEquirect(env, 0, 1, 0);
  const auto zenith = sampleEquirect(model.radiance, 0, 1, 0);
  const auto repeated = sampleEquirect(nearest.radiance, 0, 1, 0);
  double modelError = 0.0, nearestError = 0.0;
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(zenith[c] / truth[c], 1.0, 0.10) << "channel " << c;
    modelError += std::abs(zenith[c] / truth[c] - 1.0) / 3.0;
    nearestError += std::abs(repeated[c] / truth[c] - 1.0) / 3.0;
  }
  EXPECT_LT(modelError, 0.5 * nearestError);
  // The seam: along each column, the step from the last seen row to the first filled row above
  // it is the truth's step between those rows (a few % per row there), not more.
  const int w = model.radiance.width, h = model.radiance.height;
  auto truthAt = [&](int x, int y) {
    const auto d = equirectTexelDirection(w, h, x, y);
    return sampleEquirect(env, float(d[0]), float(d[1]), float(d[2]));
  };
  double worstExcess = 0.0;
  int edges = 0;
  for (int x = 0; x < w; ++x)
    for (int y = 1; y < h / 2; ++y) {
      if (model.coverage.at<uchar>(y - 1, x) || !model.coverage.at<uchar>(y, x)) continue;
      ++edges;
      const float* filled = model.radiance.texel(x, y - 1);
      const float* seen = model.radiance.texel(x, y);
      const auto above = truthAt(x, y - 1), below = truthAt(x, y);
      for (size_t c = 0; c < 3; ++c) {
        const double step = std::abs(std::log(double(filled[c]) / seen[c]));
        const double truthStep = std::abs(std::log(double(above[c]) / below[c]));
        worstExcess = std::max(worstExcess, step - truthStep);
      }
    }
  EXPECT_EQ(edges, w);
  EXPECT_LT(worstExcess, 0.02);
  EXPECT_TRUE(allFinite(model.radiance));
}

TEST(Panorama, PanThatAlsoTiltsIsPlacedAndCoversMore) {
  // A pan whose every other frame looks 25° up: placed with the tilt (relative to frame 0, which
  // is level), and its panorama covers more of the sphere than the level pan's.
  const EquirectMap env = texturedEnvironment();
  const std::vector<double> yaws = {0, 20, 40, 60, 80, 100, 120};
  const std::vector<double> pitches = {0, 25, 0, 25, 0, 25, 0};
  const int w = 640, h = 360;
  const double fov = 60.0;
  std::vector<PanoramaFrame> frames;
  for (size_t k = 0; k < yaws.size(); ++k)
    frames.push_back(recordView(env, panPose(yaws[k], pitches[k], fov, w), w, h, 1.0).frame);
  PlacementSettings settings;
  settings.horizontalFovDeg = fov;
  const Placement placement = placeFrames(frames, settings);
  ASSERT_TRUE(placement.fromFeatures) << placement.note;
  double worstPitch = 0, worstYaw = 0;
  for (size_t k = 0; k < yaws.size(); ++k) {
    worstPitch = std::max(
        worstPitch, std::abs(std::asin(forwardOf(placement.poses[k])[1]) / kDeg - pitches[k]));
    worstYaw = std::max(worstYaw, std::abs(wrapDeg(yawOf(placement.poses[k]) - yaws[k])));
  }
  EXPECT_LT(worstPitch, 1.0);
  EXPECT_LT(worstYaw, 1.0);
  EquirectSettings es;
  es.width = 512;
  const PanoramaResult tilted = renderEquirect(frames, placement, es);
  const PanoramaResult level = renderEquirect(cutFrames(env, yaws, 0.0, fov, w, h, {1.0}),
                                              knownPlacement(yaws, 0.0, fov, w), es);
  EXPECT_GT(tilted.coveredFraction, 1.2 * level.coveredFraction);
  EXPECT_LT(coveredRelativeError(tilted, env, 1.0), 0.05);
}

TEST(Panorama, RealHdrPanRecoversYawAndFocal) {
  const auto dir = test::sharedData();
  if (dir.empty() || !std::filesystem::exists(dir / "hdr" / "blender_world_city.exr"))
    GTEST_SKIP() << "no ../shared/data/hdr";
  const EquirectMap env =
      optics::loadEnvironment((dir / "hdr" / "blender_world_city.exr").string());
  const std::vector<double> yaws = {0, 20, 40, 60, 80, 100};
  const int w = 640, h = 360;
  // Expose the median radiance to mid grey.
  std::vector<float> lum;
  for (std::size_t i = 0; i < env.rgb.size(); i += 3) lum.push_back(env.rgb[i + 1]);
  std::nth_element(lum.begin(), lum.begin() + lum.size() / 2, lum.end());
  const double exposure = 0.18 / std::max(1e-6f, lum[lum.size() / 2]);
  const auto frames = cutFrames(env, yaws, 0.0, 60.0, w, h, {exposure});
  PlacementSettings settings;
  settings.horizontalFovDeg = 55.0;
  const Placement placement = placeFrames(frames, settings);
  ASSERT_TRUE(placement.fromFeatures) << placement.note;
  const double trueFocal = panPose(0, 0, 60.0, w).focalPx;
  double worstYaw = 0, worstFocal = 0;
  for (std::size_t k = 0; k < yaws.size(); ++k) {
    worstYaw = std::max(worstYaw, std::abs(wrapDeg(yawOf(placement.poses[k]) - yaws[k])));
    worstFocal = std::max(worstFocal, std::abs(placement.poses[k].focalPx / trueFocal - 1.0));
  }
  std::printf("city HDR pan: worst yaw error %.3f deg, focal %.2f %%\n", worstYaw,
              100 * worstFocal);
  EXPECT_LT(worstYaw, 1.0);
  EXPECT_LT(worstFocal, 0.03);
  EquirectSettings es;
  es.width = 512;  // the HDR is 1k: at its own resolution a 0.3 degree error is a texel
  const PanoramaResult pano = renderEquirect(frames, placement, es);
  const double err = coveredRelativeError(pano, env, exposure);
  const PanoramaResult known = renderEquirect(frames, knownPlacement(yaws, 0.0, 60.0, w), es);
  const double knownErr = coveredRelativeError(known, env, exposure);
  std::printf("city HDR pan (%dx%d): mean relative error %.4f (known poses: %.4f)\n", env.width,
              env.height, err, knownErr);
  // The render itself is exact; the city's hard, dark-against-bright edges turn the placement's
  // few tenths of a degree into a larger mean relative error than the textured synthetic scene.
  EXPECT_LT(knownErr, 0.05);
  EXPECT_LT(err, 0.2);
}

TEST(Panorama, BlankFramesFallBackWithANote) {
  std::vector<PanoramaFrame> frames;
  for (int k = 0; k < 4; ++k)
    frames.push_back({cv::Mat(180, 320, CV_32FC3, cv::Scalar::all(0.3)), cv::Mat()});
  PlacementSettings settings;
  settings.horizontalFovDeg = 50.0;
  settings.fallbackYawPerFrameDeg = 15.0;
  Placement placement;
  ASSERT_NO_THROW(placement = placeFrames(frames, settings));
  EXPECT_FALSE(placement.fromFeatures);
  EXPECT_FALSE(placement.note.empty());
  ASSERT_EQ(placement.poses.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    const CameraPose expected = panPose(15.0 * k, 0.0, 50.0, 320);
    EXPECT_NEAR(placement.poses[k].focalPx, expected.focalPx, 1e-9);
    EXPECT_NEAR(yawOf(placement.poses[k]), 15.0 * k, 1e-9);
  }
  // Nothing at all, and empty images: no throw either.
  EXPECT_NO_THROW(placeFrames({}, settings));
  EXPECT_NO_THROW(placeFrames({PanoramaFrame{}, PanoramaFrame{}}, settings));
  const PanoramaResult pano = renderEquirect(frames, placement, EquirectSettings{});
  EXPECT_TRUE(allFinite(pano.radiance));
  EXPECT_NEAR(pano.radiance.texel(3, 3)[0], 0.3, 1e-5);  // a pole, filled with the nearest
}

TEST(Panorama, SingleFrameLooksAlongMinusZAndCoversItsFrustum) {
  const EquirectMap env = lab::builtinTestEnvironment(1024);
  const int w = 640, h = 360;
  const auto frames = cutFrames(env, {0.0}, 0.0, 60.0, w, h, {0.5});
  PlacementSettings settings;
  settings.horizontalFovDeg = 60.0;
  const Placement placement = placeFrames(frames, settings);
  ASSERT_EQ(placement.poses.size(), 1u);
  EXPECT_LT(cv::norm(placement.poses[0].cameraToWorld - cv::Matx33d::eye()), 1e-12);
  EquirectSettings es;
  es.width = 1024;
  const PanoramaResult pano = renderEquirect(frames, placement, es);
  const double a = 30.0 * kDeg;
  const double b = std::atan(std::tan(a) * h / w);
  const double frustum = 4.0 * std::asin(std::sin(a) * std::sin(b)) / (4.0 * CV_PI);
  std::printf("single frame: covered %.5f, frustum %.5f\n", pano.coveredFraction, frustum);
  EXPECT_NEAR(pano.coveredFraction / frustum, 1.0, 0.03);
  EXPECT_TRUE(allFinite(pano.radiance));
  // The centre texel (looking along -Z) is covered and matches the environment.
  const int cx = es.width / 2, cy = es.width / 4;
  EXPECT_TRUE(pano.coverage.at<uchar>(cy, cx));
  EXPECT_FALSE(pano.coverage.at<uchar>(cy, 0));
  // Behind the camera: filled with a seen colour (not black).
  EXPECT_GT(pano.radiance.texel(0, cy)[0], 0.0f);
}

TEST(Panorama, FullTurnIsContinuousAcrossTheSeam) {
  const EquirectMap env = texturedEnvironment();
  std::vector<double> yaws;
  for (int k = 0; k < 12; ++k) yaws.push_back(30.0 * k);
  const int w = 480, h = 270;
  const auto frames = cutFrames(env, yaws, 0.0, 60.0, w, h, {1.0});
  // Placement by features across the full turn.
  PlacementSettings settings;
  settings.horizontalFovDeg = 60.0;
  const Placement placed = placeFrames(frames, settings);
  ASSERT_TRUE(placed.fromFeatures) << placed.note;
  double worstStep = 0;
  for (int k = 1; k < 12; ++k)
    worstStep = std::max(
        worstStep, std::abs(wrapDeg(yawOf(placed.poses[k]) - yawOf(placed.poses[k - 1]) - 30.0)));
  std::printf("full turn: worst yaw step error %.3f deg\n", worstStep);
  EXPECT_LT(worstStep, 1.0);

  EquirectSettings es;
  es.width = 1024;
  const PanoramaResult pano = renderEquirect(frames, placed, es);
  EXPECT_TRUE(allFinite(pano.radiance));
  // Seam: columns 0 and width-1 are neighbours; their difference is like any neighbours'.
  const int W = pano.radiance.width, H = pano.radiance.height;
  auto columnDiff = [&](int a, int b) {
    double s = 0;
    for (int y = H / 4; y < 3 * H / 4; ++y)
      for (int c = 0; c < 3; ++c)
        s += std::abs(pano.radiance.texel(a, y)[c] - pano.radiance.texel(b, y)[c]);
    return s / (H / 2 * 3);
  };
  double typical = 0;
  for (int x = 0; x + 1 < W; ++x) typical += columnDiff(x, x + 1);
  typical /= W - 1;
  const double seam = columnDiff(W - 1, 0);
  std::printf("full turn: seam difference %.4f, typical neighbour difference %.4f\n", seam,
              typical);
  EXPECT_LT(seam, 3.0 * typical);
  EXPECT_GT(pano.coveredFraction, 0.25);
  // The panorama matches the environment near the seam too.
  EXPECT_LT(coveredRelativeError(pano, env, 1.0), 0.06);
}

TEST(Panorama, ExposureGainsRecoverTheRatio) {
  const EquirectMap env = texturedEnvironment();
  const std::vector<double> yaws = {0, 20, 40, 60, 80, 100};
  const int w = 480, h = 270;
  const auto frames = cutFrames(env, yaws, 0.0, 60.0, w, h, {0.5, 1.0});
  const Placement placement = knownPlacement(yaws, 0.0, 60.0, w);
  EquirectSettings es;
  es.width = 512;
  const PanoramaResult pano = renderEquirect(frames, placement, es);
  ASSERT_EQ(pano.gains.size(), yaws.size());
  EXPECT_FLOAT_EQ(pano.gains[0], 1.0f);
  for (std::size_t k = 0; k < yaws.size(); ++k) {
    std::printf("gain %zu: %.4f\n", k, pano.gains[k]);
    EXPECT_NEAR(pano.gains[k], k % 2 ? 0.5 : 1.0, (k % 2 ? 0.5 : 1.0) * 0.05);
  }
  EXPECT_LT(coveredRelativeError(pano, env, 0.5), 0.06);
}

TEST(Panorama, BrightSunClipsAndTakesTheLightsRadiance) {
  EquirectMap env = lab::builtinTestEnvironment(1024);
  const double el = 30.0 * kDeg, az = 0.6;
  const std::array<double, 3> sun = {std::cos(el) * std::sin(az), std::sin(el),
                                     -std::cos(el) * std::cos(az)};
  for (float& v : env.rgb)
    if (v > 100.0f) v = 1e5f;  // the built-in sun, now 1e5 times the sky
  const std::vector<double> yaws = {0, 20, 40, 60};
  const int w = 480, h = 270;
  const auto frames = cutFrames(env, yaws, 20.0, 60.0, w, h, {0.7});
  int clipped = 0;
  for (const auto& f : frames) clipped += cv::countNonZero(f.saturated);
  EXPECT_GT(clipped, 0);
  double maxFrame = 0;
  for (const auto& f : frames) {
    double m;
    cv::minMaxLoc(f.linearRgb.reshape(1), nullptr, &m);
    maxFrame = std::max(maxFrame, m);
  }
  EXPECT_LE(maxFrame, 1.0);
  const Placement placement = knownPlacement(yaws, 20.0, 60.0, w);

  EquirectSettings es;
  es.width = 1024;
  LightSource light;
  light.direction = sun;
  light.radiusDeg = 1.5;
  light.radiance = {1e5f, 0.9e5f, 0.75e5f};
  es.lights.push_back(light);
  const PanoramaResult pano = renderEquirect(frames, placement, es);
  EXPECT_TRUE(allFinite(pano.radiance));
  const auto uv = equirectUv(sun);
  const int sx = int(uv[0] * es.width), sy = int(uv[1] * es.width / 2);
  EXPECT_FLOAT_EQ(pano.radiance.texel(sx, sy)[0], 1e5f);
  EXPECT_FLOAT_EQ(pano.radiance.texel(sx, sy)[2], 0.75e5f);
  int sunTexels = 0;
  for (int y = 0; y < pano.radiance.height; ++y)
    for (int x = 0; x < pano.radiance.width; ++x)
      if (pano.radiance.texel(x, y)[0] == 1e5f) ++sunTexels;
  EXPECT_GT(sunTexels, 10);
  // Without the light the sun keeps its clipped value (times the frame's gain).
  const PanoramaResult bare = renderEquirect(frames, placement, EquirectSettings{1024, {}});
  EXPECT_TRUE(allFinite(bare.radiance));
  EXPECT_LT(bare.radiance.texel(sx, sy)[0], 1.5f);
  EXPECT_GT(bare.radiance.texel(sx, sy)[0], 0.9f);

  // A frame-region light: the saturated pixels inside that rectangle of frame 1.
  EquirectSettings regionSettings;
  regionSettings.width = 1024;
  LightSource region;
  region.frame = 1;
  region.region = cv::Rect(0, 0, w, h);
  region.radiance = {5e4f, 5e4f, 5e4f};
  regionSettings.lights.push_back(region);
  const PanoramaResult byRegion = renderEquirect(frames, placement, regionSettings);
  EXPECT_TRUE(allFinite(byRegion.radiance));
  EXPECT_FLOAT_EQ(byRegion.radiance.texel(sx, sy)[1], 5e4f);
}

// A lamp at the top edge of the frames, given its radiance as a frame-region light: the light
// replaces the saturated pixels it covers, and the unseen sky above is filled from what the
// footage recorded (the clipped value), never with copies of the light, which would multiply
// its power over the whole unseen cap.
TEST(Panorama, RegionLightAtTheEdgeIsNotSpreadByTheFill) {
  EquirectMap env = uniformEquirect(512, 256, {0.2f, 0.2f, 0.2f});
  // Frames of 60 deg x about 36 deg at pitch 0: the top edge at about 18 deg elevation.
  for (int y = 0; y < env.height; ++y)
    for (int x = 0; x < env.width; ++x) {
      const auto d = equirectTexelDirection(env.width, env.height, x, y);
      const double elevation = std::asin(d[1]) / kDeg, azimuth = std::atan2(d[0], -d[2]) / kDeg;
      if (elevation > 12.0 && elevation < 30.0 && std::abs(azimuth) < 8.0)
        for (int c = 0; c < 3; ++c) env.texel(x, y)[c] = 1e3f;
    }
  const std::vector<double> yaws = {-20, 0, 20};
  const int w = 320, h = 180;
  const auto frames = cutFrames(env, yaws, 0.0, 60.0, w, h, {1.0});
  EquirectSettings settings;
  settings.width = 512;
  LightSource lamp;
  lamp.frame = 1;
  lamp.region = cv::Rect(0, 0, w, h / 4);
  lamp.radiance = {1e3f, 1e3f, 1e3f};
  settings.lights.push_back(lamp);
  const PanoramaResult pano = renderEquirect(frames, knownPlacement(yaws, 0.0, 60.0, w), settings);
  ASSERT_TRUE(allFinite(pano.radiance));
  int seenLamp = 0;
  float unseenMax = 0.0f;
  for (int y = 0; y < pano.radiance.height; ++y)
    for (int x = 0; x < pano.radiance.width; ++x) {
      const float v = pano.radiance.texel(x, y)[1];
      if (pano.coverage.at<uchar>(y, x))
        seenLamp += v == 1e3f;
      else
        unseenMax = std::max(unseenMax, v);
    }
  EXPECT_GT(seenLamp, 10) << "the lamp's saturated pixels take its radiance";
  EXPECT_LE(unseenMax, 1.0f) << "the fill spread the lamp over the unseen directions";
}

TEST(Panorama, WeirPhotosPlaceLeftToRight) {
  const auto dir = test::sharedData();
  const auto weir = dir / "stitching" / "weir";
  if (dir.empty() || !std::filesystem::exists(weir / "weir_1.jpg"))
    GTEST_SKIP() << "no ../shared/data/stitching/weir";
  std::vector<PanoramaFrame> frames;
  for (int k = 1; k <= 3; ++k) {
    cv::Mat bgr = cv::imread((weir / ("weir_" + std::to_string(k) + ".jpg")).string());
    ASSERT_FALSE(bgr.empty());
    cv::Mat rgb;
    cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
    rgb.convertTo(rgb, CV_32FC3, 1.0 / 255.0);
    rgb.forEach<cv::Vec3f>([](cv::Vec3f& p, const int*) {
      for (int c = 0; c < 3; ++c)
        p[c] = p[c] <= 0.04045f ? p[c] / 12.92f : std::pow((p[c] + 0.055f) / 1.055f, 2.4f);
    });
    frames.push_back({rgb, cv::Mat()});
  }
  PlacementSettings settings;
  settings.horizontalFovDeg = 50.0;
  const Placement placement = placeFrames(frames, settings);
  ASSERT_TRUE(placement.fromFeatures) << placement.note;
  for (int k = 0; k < 3; ++k)
    std::printf("weir %d: yaw %.2f deg, pitch %.2f deg, focal %.1f px\n", k + 1,
                yawOf(placement.poses[k]), std::asin(forwardOf(placement.poses[k])[1]) / kDeg,
                placement.poses[k].focalPx);
  EXPECT_GT(yawOf(placement.poses[1]), yawOf(placement.poses[0]) + 1.0);
  EXPECT_GT(yawOf(placement.poses[2]), yawOf(placement.poses[1]) + 1.0);
  const PanoramaResult pano = renderEquirect(frames, placement, EquirectSettings{});
  EXPECT_TRUE(allFinite(pano.radiance));
  EXPECT_GT(pano.coveredFraction, 0.02);
}

}  // namespace
}  // namespace pluvia::envmap
