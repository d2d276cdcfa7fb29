// Camera poses of a panning shot's frames from OpenCV's stitching pipeline (ORB features,
// best-of-2-nearest matching, homography-based rotation estimate, ray bundle adjustment).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <numeric>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/stitching/detail/matchers.hpp>
#include <opencv2/stitching/detail/motion_estimators.hpp>

#include "envmap/panorama.h"
#include "envmap/perspective_view.h"
#include "image/resize.h"
#include "image/srgb.h"
#include "util/interrupt.h"

namespace pluvia::envmap {
namespace {

constexpr double kFeatureMegapixels = 0.6;
constexpr double kMinPairConfidence = 1.0;  // OpenCV stitching_detailed's default threshold
constexpr size_t kMinKeypoints = 20;        // fewer: the frame is placed by interpolation

// 8-bit BGR (sRGB-encoded, clipped) of a linear RGB frame, downscaled by `scale`.
cv::Mat featureImage(const cv::Mat& linearRgb, double scale) {
  cv::Mat small;
  if (scale < 1.0) {
    cv::resize(linearRgb, small, scaledSize(linearRgb.cols, linearRgb.rows, scale), 0, 0,
               cv::INTER_AREA);
  } else {
    small = linearRgb;
  }
  cv::Mat out(small.size(), CV_8UC3);
  std::array<uchar, 4096> lut{};
  for (int i = 0; i < 4096; ++i) {
    const double v = i / 4095.0;
    const double e = srgbEncode(v);
    lut[i] = uchar(std::clamp(int(std::lround(e * 255.0)), 0, 255));
  }
  for (int y = 0; y < small.rows; ++y) {
    const auto* in = small.ptr<cv::Vec3f>(y);
    auto* o = out.ptr<cv::Vec3b>(y);
    for (int x = 0; x < small.cols; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float v = in[x][c];
        const int idx = std::isfinite(v) ? std::clamp(int(v * 4095.0f + 0.5f), 0, 4095) : 0;
        o[x][2 - c] = lut[idx];  // RGB -> BGR
      }
    }
  }
  return out;
}

Placement fallback(const std::vector<PanoramaFrame>& frames, const PlacementSettings& settings,
                   const std::string& why) {
  Placement p;
  p.fromFeatures = false;
  p.note = why;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const int w = std::max(1, frames[k].linearRgb.cols);
    p.poses.push_back(
        panPose(double(k) * settings.fallbackYawPerFrameDeg, 0.0, settings.horizontalFovDeg, w));
  }
  return p;
}

// Poses for all `count` frames from those of the `featured` ones (in increasing order): a frame
// between two placed ones turns along the rotation between them (its share of the way by
// index) with the focal length interpolated; one before the first or after the last takes the
// nearest. Lists the frames so placed in `interpolated`.
std::vector<CameraPose> interpolatePoses(int count, const std::vector<int>& featured,
                                         const std::vector<CameraPose>& placed,
                                         std::vector<int>& interpolated) {
  std::vector<CameraPose> poses(static_cast<size_t>(count));
  size_t next = 0;  // the first featured frame at or after k
  for (int k = 0; k < count; ++k) {
    while (next < featured.size() && featured[next] < k) ++next;
    if (next < featured.size() && featured[next] == k) {
      poses[size_t(k)] = placed[next];
      continue;
    }
    interpolated.push_back(k);
    if (next == 0 || next == featured.size()) {
      poses[size_t(k)] = placed[next == 0 ? 0 : featured.size() - 1];
      continue;
    }
    const CameraPose& a = placed[next - 1];
    const CameraPose& b = placed[next];
    const double t = double(k - featured[next - 1]) / double(featured[next] - featured[next - 1]);
    cv::Vec3d turn;
    cv::Rodrigues(cv::Mat(a.cameraToWorld.t() * b.cameraToWorld), turn);
    cv::Mat partial;
    cv::Rodrigues(turn * t, partial);
    poses[size_t(k)].cameraToWorld = a.cameraToWorld * cv::Matx33d(partial);
    poses[size_t(k)].focalPx = (1.0 - t) * a.focalPx + t * b.focalPx;
  }
  return poses;
}

bool finite(const cv::Matx33d& m) {
  for (int i = 0; i < 9; ++i)
    if (!std::isfinite(m.val[i])) return false;
  return true;
}

}  // namespace

Placement placeFrames(const std::vector<PanoramaFrame>& frames, const PlacementSettings& settings) {
  const int n = int(frames.size());
  if (n == 0) return fallback(frames, settings, "no frames to place");
  if (n == 1) {
    Placement p = fallback(frames, settings, "");
    p.fromFeatures = false;
    p.note = "a single frame: placed looking along -Z";
    return p;
  }
  for (const auto& f : frames) {
    if (f.linearRgb.empty() || f.linearRgb.type() != CV_32FC3)
      return fallback(frames, settings, "a frame is empty or not float RGB");
  }

  try {
    namespace cd = cv::detail;
    std::vector<double> scales(n);
    std::vector<cv::Mat> images(n);
    for (int k = 0; k < n; ++k) {
      const double area = double(frames[k].linearRgb.total());
      scales[k] = std::min(1.0, std::sqrt(kFeatureMegapixels * 1e6 / area));
      images[k] = featureImage(frames[k].linearRgb, scales[k]);
    }

    std::vector<cd::ImageFeatures> all(n);
    cv::Ptr<cv::Feature2D> orb = cv::ORB::create(1500);
    cd::computeImageFeatures(orb, images, all);
    throwIfInterrupted();  // between the feature and the matching passes, the long ones
    // Frames with too few features (sky, fog, a blank wall, a flash) are left out of the
    // matching and placed afterwards between their neighbours.
    std::vector<int> featured;
    std::vector<cd::ImageFeatures> features;
    for (int k = 0; k < n; ++k) {
      if (all[k].keypoints.size() < kMinKeypoints) continue;
      // Keypoints put pixel centres at integers; the estimators' principal point (w / 2, h / 2)
      // is in edge coordinates (pixel centres at + 0.5): shift so both agree.
      for (auto& kp : all[k].keypoints) kp.pt += cv::Point2f(0.5f, 0.5f);
      all[k].img_idx = int(features.size());
      featured.push_back(k);
      features.push_back(all[k]);
    }
    if (featured.size() < std::max<size_t>(2, size_t(n) / 2))
      return fallback(frames, settings,
                      fmt::format("{} of {} frames have too few features to match (sky, fog, a "
                                  "blank wall?)",
                                  n - int(featured.size()), n));
    const int m = int(featured.size());

    // A panning shot: match each frame with its neighbours (cyclic, so a full turn closes).
    const int band = m <= 8 ? m : 4;
    cv::Mat mask(m, m, CV_8U, cv::Scalar(0));
    for (int i = 0; i < m; ++i)
      for (int j = 0; j < m; ++j) {
        const int d = std::abs(i - j);
        if (i != j && std::min(d, m - d) <= band) mask.at<uchar>(i, j) = 1;
      }
    std::vector<cd::MatchesInfo> pairwise;
    cd::BestOf2NearestMatcher matcher(false, 0.3f);
    matcher(features, pairwise, mask.getUMat(cv::ACCESS_READ));
    matcher.collectGarbage();

    // Every frame must be linked to the others by confident matches.
    std::vector<cd::ImageFeatures> featuresCopy = features;
    std::vector<cd::MatchesInfo> pairwiseCopy = pairwise;
    const std::vector<int> kept =
        cd::leaveBiggestComponent(featuresCopy, pairwiseCopy, float(kMinPairConfidence));
    if (int(kept.size()) < m)
      return fallback(frames, settings,
                      fmt::format("only {} of {} frames are linked by confident feature matches",
                                  kept.size(), m));

    std::vector<cd::CameraParams> cameras;
    cd::HomographyBasedEstimator estimator;
    if (!estimator(features, pairwise, cameras) || int(cameras.size()) != m)
      return fallback(frames, settings, "the homography-based rotation estimate failed");

    // Seed the focal from the field of view when the homographies gave nothing sensible.
    const double seedFocal =
        0.5 * images[size_t(featured[0])].cols /
        std::tan(std::clamp(settings.horizontalFovDeg, 1.0, 179.0) * CV_PI / 360.0);
    for (auto& cam : cameras) {
      cam.R.convertTo(cam.R, CV_32F);
      if (!std::isfinite(cam.focal) || cam.focal < seedFocal / 4 || cam.focal > seedFocal * 4)
        cam.focal = seedFocal;
    }

    cd::BundleAdjusterRay adjuster;
    adjuster.setConfThresh(kMinPairConfidence);
    if (!adjuster(features, pairwise, cameras))
      return fallback(frames, settings, "bundle adjustment did not converge");

    // OpenCV's R maps a camera ray K^-1 (x, y, 1) (+X right, +Y down, +Z forward) to the world;
    // ours has +Y up and -Z forward: flip both frames with F = diag(1, -1, -1).
    const cv::Matx33d flip(1, 0, 0, 0, -1, 0, 0, 0, -1);
    std::vector<CameraPose> placed(static_cast<size_t>(m));
    for (int j = 0; j < m; ++j) {
      const int k = featured[size_t(j)];
      cv::Mat r64;
      cameras[size_t(j)].R.convertTo(r64, CV_64F);
      placed[size_t(j)].cameraToWorld = flip * cv::Matx33d(r64) * flip;
      placed[size_t(j)].focalPx = cameras[size_t(j)].focal / scales[size_t(k)];
      if (!finite(placed[size_t(j)].cameraToWorld) || !std::isfinite(placed[size_t(j)].focalPx) ||
          placed[size_t(j)].focalPx <= 0)
        return fallback(frames, settings, "bundle adjustment gave a degenerate camera");
    }
    Placement p;
    p.fromFeatures = true;
    p.poses = interpolatePoses(n, featured, placed, p.interpolated);
    if (!p.interpolated.empty())
      p.note = fmt::format("frames {} have too few features: placed between their neighbours",
                           fmt::join(p.interpolated, ", "));
    // Re-reference: frame 0 looks along -Z.
    const cv::Matx33d ref = p.poses[0].cameraToWorld.t();
    for (auto& pose : p.poses) {
      pose.cameraToWorld = ref * pose.cameraToWorld;
      // Re-orthonormalise against drift.
      cv::SVD svd(cv::Mat(pose.cameraToWorld));
      pose.cameraToWorld = cv::Matx33d(cv::Mat(svd.u * svd.vt));
    }
    return p;
  } catch (const Interrupted&) {
    throw;
  } catch (const std::exception& e) {
    return fallback(frames, settings, std::string("feature placement failed: ") + e.what());
  }
}

}  // namespace pluvia::envmap
