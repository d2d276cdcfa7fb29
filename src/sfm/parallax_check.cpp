#include "sfm/parallax_check.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "image/resize.h"

namespace pluvia::sfm {
namespace {

cv::Mat grey8(const cv::Mat& frame, int maxSizePx) {
  cv::Mat grey = frame;
  if (frame.channels() == 3) cv::cvtColor(frame, grey, cv::COLOR_RGB2GRAY);
  if (frame.channels() == 4) cv::cvtColor(frame, grey, cv::COLOR_RGBA2GRAY);
  if (grey.depth() != CV_8U) grey.convertTo(grey, CV_8U, 255.0);
  const double scale = double(maxSizePx) / std::max(grey.cols, grey.rows);
  if (scale < 1.0)
    cv::resize(grey, grey, scaledSize(grey.cols, grey.rows, scale), 0, 0, cv::INTER_AREA);
  return grey;
}

}  // namespace

ParallaxProbe::ParallaxProbe(const std::vector<cv::Mat>& frames,
                             const ParallaxCheckSettings& settings)
    : settings_(settings) {
  auto sift = cv::SIFT::create(2000);
  for (const cv::Mat& frame : frames) {
    Features f;
    sift->detectAndCompute(grey8(frame, settings.maxImageSizePx), cv::noArray(), f.points,
                           f.descriptors);
    features_.push_back(std::move(f));
  }
}

double ParallaxProbe::parallaxFraction(size_t a, size_t b, int* inliersOut) const {
  if (inliersOut) *inliersOut = 0;
  const Features& fa = features_.at(a);
  const Features& fb = features_.at(b);
  if (fa.descriptors.rows < 2 || fb.descriptors.rows < 2) return 0.0;
  // Matches passing Lowe's ratio test.
  cv::BFMatcher matcher(cv::NORM_L2);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(fa.descriptors, fb.descriptors, knn, 2);
  std::vector<cv::Point2f> pa, pb;
  for (const auto& m : knn)
    if (m.size() == 2 && m[0].distance < 0.75f * m[1].distance) {
      pa.push_back(fa.points[size_t(m[0].queryIdx)].pt);
      pb.push_back(fb.points[size_t(m[0].trainIdx)].pt);
    }
  if (int(pa.size()) < settings_.minMatches) return 0.0;
  cv::Mat fundamentalInliers;
  const cv::Mat fundamental =
      cv::findFundamentalMat(pa, pb, cv::FM_RANSAC, 1.0, 0.999, fundamentalInliers);
  const cv::Mat homography = cv::findHomography(pa, pb, cv::RANSAC, settings_.parallaxThresholdPx);
  if (fundamental.empty() || homography.empty()) return 0.0;
  std::vector<cv::Point2f> mapped;
  cv::perspectiveTransform(pa, mapped, homography);
  int inliers = 0, offPlane = 0;
  for (size_t i = 0; i < pa.size(); ++i) {
    if (!fundamentalInliers.at<uchar>(int(i))) continue;
    ++inliers;
    offPlane += cv::norm(mapped[i] - pb[i]) > settings_.parallaxThresholdPx ? 1 : 0;
  }
  if (inliers < settings_.minMatches) return 0.0;
  if (inliersOut) *inliersOut = inliers;
  return double(offPlane) / inliers;
}

ParallaxCheck checkParallax(const ParallaxProbe& probe, const ParallaxCheckSettings& settings) {
  ParallaxCheck check;
  if (probe.size() < 2) return check;
  const size_t last = probe.size() - 1;
  std::vector<size_t> partners{last, last / 2, last / 4};
  partners.erase(std::remove(partners.begin(), partners.end(), size_t(0)), partners.end());
  partners.erase(std::unique(partners.begin(), partners.end()), partners.end());
  std::string measured;
  for (size_t partner : partners) {
    int inliers = 0;
    const double fraction = probe.parallaxFraction(0, partner, &inliers);
    if (inliers == 0) continue;
    ++check.pairsJudged;
    check.parallaxFraction = std::max(check.parallaxFraction, fraction);
    if (measured.empty())
      measured = fmt::format(
          "{:.0f} % of {} matches between frames 1 and {} of {} leave one "
          "homography by more than {} px",
          100.0 * fraction, inliers, partner + 1, probe.size(), settings.parallaxThresholdPx);
  }
  if (check.pairsJudged == 0) return check;
  if (check.parallaxFraction >= settings.minParallaxFraction) {
    check.verdict = ParallaxVerdict::Parallax;
    return check;
  }
  check.verdict = ParallaxVerdict::NoParallax;
  check.message = fmt::format(
      "the camera rotates without moving (a pan or a tripod): {} (under {:.0f} %), so structure "
      "from motion gives no depth",
      measured, 100.0 * settings.minParallaxFraction);
  return check;
}

ParallaxCheck checkParallax(const std::vector<cv::Mat>& frames,
                            const ParallaxCheckSettings& settings) {
  return checkParallax(ParallaxProbe(frames, settings), settings);
}

std::vector<size_t> selectKeyframes(const ParallaxProbe& probe,
                                    const ParallaxCheckSettings& settings) {
  std::vector<size_t> keys;
  if (probe.size() == 0) return keys;
  keys.push_back(0);
  int referenceInliers = -1;  // the key's matches with the frame after it
  // Measures frame j against the current key; makes it the key when it shows enough parallax.
  auto measure = [&](size_t j) {
    int inliers = 0;
    const double fraction = probe.parallaxFraction(keys.back(), j, &inliers);
    if (referenceInliers < 0) referenceInliers = inliers;
    if (fraction >= settings.keyframeParallaxFraction) {
      keys.push_back(j);
      referenceInliers = -1;
      return false;
    }
    return inliers < std::max(settings.minMatches, referenceInliers / 2);  // thinning out
  };
  for (size_t j = 1; j < probe.size(); ++j) {
    if (!measure(j)) continue;
    // Matches thin out before the parallax is reached: the frame before still matched well.
    referenceInliers = -1;
    if (j - 1 > keys.back()) {
      keys.push_back(j - 1);
      if (!measure(j)) continue;
      referenceInliers = -1;
    }
    if (keys.back() != j) keys.push_back(j);
  }
  if (keys.back() != probe.size() - 1) keys.push_back(probe.size() - 1);
  return keys;
}

}  // namespace pluvia::sfm
