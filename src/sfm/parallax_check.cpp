#include "sfm/parallax_check.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

namespace pluvia {
namespace {

cv::Mat grey8(const cv::Mat& frame, int maxSizePx) {
  cv::Mat grey = frame;
  if (frame.channels() == 3) cv::cvtColor(frame, grey, cv::COLOR_RGB2GRAY);
  if (frame.channels() == 4) cv::cvtColor(frame, grey, cv::COLOR_RGBA2GRAY);
  if (grey.depth() != CV_8U) grey.convertTo(grey, CV_8U, 255.0);
  const double scale = double(maxSizePx) / std::max(grey.cols, grey.rows);
  if (scale < 1.0) cv::resize(grey, grey, cv::Size(), scale, scale, cv::INTER_AREA);
  return grey;
}

struct Features {
  std::vector<cv::KeyPoint> points;
  cv::Mat descriptors;
};

// Matches passing Lowe's ratio test, as point pairs.
void matchPair(const Features& a, const Features& b, std::vector<cv::Point2f>& pa,
               std::vector<cv::Point2f>& pb) {
  if (a.descriptors.rows < 2 || b.descriptors.rows < 2) return;
  cv::BFMatcher matcher(cv::NORM_L2);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(a.descriptors, b.descriptors, knn, 2);
  for (const auto& m : knn)
    if (m.size() == 2 && m[0].distance < 0.75f * m[1].distance) {
      pa.push_back(a.points[size_t(m[0].queryIdx)].pt);
      pb.push_back(b.points[size_t(m[0].trainIdx)].pt);
    }
}

}  // namespace

ParallaxCheck checkParallax(const std::vector<cv::Mat>& frames,
                            const ParallaxCheckSettings& settings) {
  ParallaxCheck check;
  if (frames.size() < 2) return check;
  // The first frame against frames a quarter, half and all the way through the clip: the widest
  // baseline that still matches decides.
  const size_t last = frames.size() - 1;
  std::vector<size_t> partners{last, last / 2, last / 4};
  partners.erase(std::remove(partners.begin(), partners.end(), size_t(0)), partners.end());
  partners.erase(std::unique(partners.begin(), partners.end()), partners.end());

  auto sift = cv::SIFT::create(2000);
  auto describe = [&](size_t index) {
    Features f;
    sift->detectAndCompute(grey8(frames[index], settings.maxImageSizePx), cv::noArray(), f.points,
                           f.descriptors);
    return f;
  };
  const Features first = describe(0);
  std::string measured;
  for (size_t partner : partners) {
    std::vector<cv::Point2f> pa, pb;
    matchPair(first, describe(partner), pa, pb);
    if (int(pa.size()) < settings.minMatches) continue;
    cv::Mat fundamentalInliers;
    const cv::Mat fundamental =
        cv::findFundamentalMat(pa, pb, cv::FM_RANSAC, 1.0, 0.999, fundamentalInliers);
    const cv::Mat homography = cv::findHomography(pa, pb, cv::RANSAC, settings.parallaxThresholdPx);
    if (fundamental.empty() || homography.empty()) continue;
    std::vector<cv::Point2f> mapped;
    cv::perspectiveTransform(pa, mapped, homography);
    int inliers = 0, offPlane = 0;
    for (size_t i = 0; i < pa.size(); ++i) {
      if (!fundamentalInliers.at<uchar>(int(i))) continue;
      ++inliers;
      offPlane += cv::norm(mapped[i] - pb[i]) > settings.parallaxThresholdPx ? 1 : 0;
    }
    if (inliers < settings.minMatches) continue;
    const double fraction = double(offPlane) / inliers;
    ++check.pairsJudged;
    check.parallaxFraction = std::max(check.parallaxFraction, fraction);
    if (measured.empty())
      measured = fmt::format(
          "{:.0f} % of {} matches between frames 1 and {} of {} leave one "
          "homography by more than {} px",
          100.0 * fraction, inliers, partner + 1, frames.size(), settings.parallaxThresholdPx);
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

}  // namespace pluvia
