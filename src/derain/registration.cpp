#include "derain/registration.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "util/error.h"

namespace pluvia::derain {
namespace {

constexpr int kFeatures = 3000;
constexpr double kRatio = 0.75;  // Lowe's ratio test
constexpr double kRansacThresholdPx = 2.0;
constexpr int kMinInliers = 20;
// Corner displacement below which a frame counts as not having moved (subpixel noise of the fit).
constexpr double kStaticShiftPx = 0.5;

// 8-bit luminance with thin bright rain streaks suppressed (5x5 median), so features sit on the
// scene rather than on rain.
cv::Mat featureImage(const cv::Mat& rgb) {
  cv::Mat gray(rgb.size(), CV_8U);
  for (int y = 0; y < rgb.rows; ++y) {
    const cv::Vec3f* row = rgb.ptr<cv::Vec3f>(y);
    uint8_t* out = gray.ptr<uint8_t>(y);
    for (int x = 0; x < rgb.cols; ++x) {
      const float luminance = 0.2126f * row[x][0] + 0.7152f * row[x][1] + 0.0722f * row[x][2];
      // Perceptual-ish encoding so dark areas keep their features.
      out[x] = cv::saturate_cast<uint8_t>(255.0f * std::sqrt(std::max(0.0f, luminance)));
    }
  }
  cv::medianBlur(gray, gray, 5);
  return gray;
}

double cornerShift(const cv::Matx33d& h, cv::Size size) {
  double shift = 0.0;
  for (const cv::Point2d corner :
       {cv::Point2d(0, 0), cv::Point2d(size.width, 0), cv::Point2d(0, size.height),
        cv::Point2d(size.width, size.height)}) {
    const cv::Vec3d p = h * cv::Vec3d(corner.x, corner.y, 1.0);
    shift = std::max(shift, std::hypot(p[0] / p[2] - corner.x, p[1] / p[2] - corner.y));
  }
  return shift;
}

}  // namespace

Registration registerFrames(const std::vector<cv::Mat>& frames, int reference) {
  Registration registration;
  registration.referenceToFrame.assign(frames.size(), cv::Matx33d::eye());
  auto orb = cv::ORB::create(kFeatures);
  std::vector<std::vector<cv::KeyPoint>> keypoints(frames.size());
  std::vector<cv::Mat> descriptors(frames.size());
  for (size_t k = 0; k < frames.size(); ++k)
    orb->detectAndCompute(featureImage(frames[k]), cv::noArray(), keypoints[k], descriptors[k]);
  cv::BFMatcher matcher(cv::NORM_HAMMING);
  for (size_t k = 0; k < frames.size(); ++k) {
    if (int(k) == reference) continue;
    std::vector<cv::Point2f> fromReference, inFrame;
    if (!descriptors[k].empty() && !descriptors[size_t(reference)].empty()) {
      std::vector<std::vector<cv::DMatch>> matches;
      matcher.knnMatch(descriptors[size_t(reference)], descriptors[k], matches, 2);
      for (const auto& m : matches) {
        if (m.size() < 2 || m[0].distance >= kRatio * m[1].distance) continue;
        fromReference.push_back(keypoints[size_t(reference)][size_t(m[0].queryIdx)].pt);
        inFrame.push_back(keypoints[k][size_t(m[0].trainIdx)].pt);
      }
    }
    cv::Mat inliers;
    cv::Mat h;
    if (fromReference.size() >= size_t(kMinInliers))
      h = cv::findHomography(fromReference, inFrame, cv::RANSAC, kRansacThresholdPx, inliers);
    const int inlierCount = inliers.empty() ? 0 : cv::countNonZero(inliers);
    if (h.empty() || inlierCount < kMinInliers) {
      throw Error(
          fmt::format("cannot register frame {} of the window onto frame {}: {} matching features "
                      "(at least {} needed); is the camera moving too fast or the frame blank?",
                      k, reference, inlierCount, kMinInliers),
          {"derain"});
    }
    registration.referenceToFrame[k] = cv::Matx33d(h);
    registration.maxShiftPx = std::max(
        registration.maxShiftPx, cornerShift(registration.referenceToFrame[k], frames[k].size()));
  }
  if (registration.maxShiftPx < kStaticShiftPx) {
    // Locked-off: the fits only measured noise. Keep the frames exactly as they are.
    std::fill(registration.referenceToFrame.begin(), registration.referenceToFrame.end(),
              cv::Matx33d::eye());
  }
  return registration;
}

FrameStack warpToReference(const std::vector<cv::Mat>& frames, const Registration& registration) {
  FrameStack stack;
  if (!registration.moving()) {
    stack.frames = frames;
    return stack;
  }
  for (size_t k = 0; k < frames.size(); ++k) {
    const cv::Mat h(registration.referenceToFrame[k]);
    cv::Mat warped, valid;
    cv::warpPerspective(frames[k], warped, h, frames[k].size(),
                        cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_CONSTANT);
    const cv::Mat all(frames[k].size(), CV_8U, cv::Scalar(255));
    cv::warpPerspective(all, valid, h, frames[k].size(), cv::INTER_NEAREST | cv::WARP_INVERSE_MAP,
                        cv::BORDER_CONSTANT, cv::Scalar(0));
    // Drop the one-pixel rim where bilinear sampling mixed in the zero border.
    cv::erode(valid, valid, cv::Mat(), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(255));
    stack.frames.push_back(warped);
    stack.valid.push_back(valid);
  }
  return stack;
}

cv::Mat warpToFrame(const cv::Mat& onReference, const Registration& registration, int index,
                    cv::Mat* covered) {
  const cv::Matx33d& h = registration.referenceToFrame[size_t(index)];
  if (!registration.moving()) {
    if (covered) *covered = cv::Mat(onReference.size(), CV_8U, cv::Scalar(255));
    return onReference.clone();
  }
  cv::Mat warped;
  cv::warpPerspective(onReference, warped, cv::Mat(h), onReference.size(), cv::INTER_LINEAR,
                      cv::BORDER_CONSTANT);
  if (covered) {
    const cv::Mat all(onReference.size(), CV_8U, cv::Scalar(255));
    cv::warpPerspective(all, *covered, cv::Mat(h), onReference.size(), cv::INTER_NEAREST,
                        cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::erode(*covered, *covered, cv::Mat(), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT,
              cv::Scalar(255));
  }
  return warped;
}

}  // namespace pluvia::derain
