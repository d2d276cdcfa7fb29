#include "derain/registration.h"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "derain/dense_flow.h"
#include "image/luminance.h"
#include "util/median.h"

namespace pluvia::derain {
namespace {

constexpr int kFeatures = 3000;
constexpr double kRatio = 0.75;  // Lowe's ratio test
constexpr double kRansacThresholdPx = 2.0;
constexpr int kMinInliers = 20;
// Corner displacement below which a frame counts as not having moved (subpixel noise of the fit).
constexpr double kStaticShiftPx = 0.5;
// Phase-correlation shift below which the camera counts as locked off.
constexpr double kStillShiftPx = 0.5;
// A frame whose contrast (standard deviation of its luminance) is below this share of the
// window's median is blank.
constexpr double kBlankContrast = 0.25;
// A phase-correlation peak below this is no evidence either way (a featureless tile).
constexpr double kMinPeakResponse = 0.05;

// 8-bit luminance with thin bright rain streaks suppressed (5x5 median), so features sit on the
// scene rather than on rain.
cv::Mat featureImage(const cv::Mat& rgb) {
  cv::Mat gray(rgb.size(), CV_8U);
  for (int y = 0; y < rgb.rows; ++y) {
    const cv::Vec3f* row = rgb.ptr<cv::Vec3f>(y);
    uint8_t* out = gray.ptr<uint8_t>(y);
    for (int x = 0; x < rgb.cols; ++x) {
      const float luminance = rec709LuminanceFloat(&row[x][0]);
      // Perceptual-ish encoding so dark areas keep their features.
      out[x] = cv::saturate_cast<uint8_t>(255.0f * std::sqrt(std::max(0.0f, luminance)));
    }
  }
  cv::medianBlur(gray, gray, 5);
  return gray;
}

// The per-pixel median of images [first, last).
cv::Mat medianOf(const std::vector<cv::Mat>& images, size_t first, size_t last) {
  cv::Mat median(images.front().size(), CV_32F);
  std::vector<float> values(last - first);
  for (int y = 0; y < median.rows; ++y)
    for (int x = 0; x < median.cols; ++x) {
      for (size_t k = first; k < last; ++k) values[k - first] = images[k].at<float>(y, x);
      median.at<float>(y, x) = medianInPlace(values.data(), values.size());
    }
  return median;
}

// A locked-off camera, told before any feature is matched: the temporal medians of the first
// and the last third of the window (so the rain, fresh in every frame, is gone from both) are
// phase-correlated in each quadrant of the frame, and no quadrant but at most one has moved by
// kStillShiftPx (a pan, a zoom or a turn moves them all; a quadrant without a clear peak, a
// featureless sky, is no evidence either way). Blank frames are left out of the medians.
// `features`: the frames' featureImage.
bool cameraIsStill(const std::vector<cv::Mat>& features) {
  std::vector<cv::Mat> all;
  std::vector<double> contrast;
  for (const cv::Mat& feature : features) {
    cv::Mat image;
    feature.convertTo(image, CV_32F);
    cv::Scalar mean, deviation;
    cv::meanStdDev(image, mean, deviation);
    all.push_back(image);
    contrast.push_back(deviation[0]);
  }
  // Blank frames (a flash, a cut to black, a lens cap) say nothing of the camera's motion.
  const double typical = median(contrast);
  std::vector<cv::Mat> images;
  for (size_t k = 0; k < all.size(); ++k)
    if (contrast[k] >= kBlankContrast * typical) images.push_back(all[k]);
  if (images.size() < 2) return false;
  const size_t third = std::max<size_t>(1, images.size() / 3);
  const cv::Mat early = medianOf(images, 0, third);
  const cv::Mat late = medianOf(images, images.size() - third, images.size());
  const cv::Size quadrant(early.cols / 2, early.rows / 2);
  if (quadrant.width < 16 || quadrant.height < 16) return false;
  cv::Mat window;
  cv::createHanningWindow(window, quadrant, CV_32F);
  std::vector<double> shifts;
  for (int qy = 0; qy < 2; ++qy)
    for (int qx = 0; qx < 2; ++qx) {
      const cv::Rect tile(qx * quadrant.width, qy * quadrant.height, quadrant.width,
                          quadrant.height);
      double response = 0.0;
      const cv::Point2d shift = cv::phaseCorrelate(early(tile), late(tile), window, &response);
      if (response >= kMinPeakResponse) shifts.push_back(std::hypot(shift.x, shift.y));
    }
  std::sort(shifts.rbegin(), shifts.rend());
  return shifts.empty() || shifts[std::min<size_t>(1, shifts.size() - 1)] < kStillShiftPx;
}

// The mean absolute difference of the frames' rain-suppressed images from the reference's, each
// resampled by `referenceToFrame` onto the reference grid and compared where it covers it.
double temporalResidual(const std::vector<cv::Mat>& features, int reference,
                        const std::vector<cv::Matx33d>& referenceToFrame) {
  double sum = 0.0, count = 0.0;
  const cv::Mat& target = features[size_t(reference)];
  const cv::Mat ones(target.size(), CV_8U, cv::Scalar(255));
  for (size_t k = 0; k < features.size(); ++k) {
    if (int(k) == reference) continue;
    // Headers of the frame's own image, or new images: a warp must not write into its source.
    cv::Mat warped, covered;
    if (referenceToFrame[k] == cv::Matx33d::eye()) {
      warped = features[k];
      covered = ones;
    } else {
      const cv::Mat h(referenceToFrame[k]);
      const int flags = cv::INTER_LINEAR | cv::WARP_INVERSE_MAP;
      cv::warpPerspective(features[k], warped, h, target.size(), flags, cv::BORDER_CONSTANT);
      cv::warpPerspective(ones, covered, h, target.size(), cv::INTER_NEAREST | cv::WARP_INVERSE_MAP,
                          cv::BORDER_CONSTANT);
    }
    cv::Mat difference;
    cv::absdiff(warped, target, difference);
    const double pixels = cv::countNonZero(covered);
    if (pixels > 0.0) sum += cv::mean(difference, covered)[0] * pixels;
    count += pixels;
  }
  return count > 0.0 ? sum / count : 0.0;
}

// keepMotionThatExplains on the frames' featureImage.
void keepMotionExplaining(const std::vector<cv::Mat>& features, int reference,
                          Registration& registration) {
  const std::vector<cv::Matx33d> identity(features.size(), cv::Matx33d::eye());
  registration.identityResidual = temporalResidual(features, reference, identity);
  registration.motionResidual =
      temporalResidual(features, reference, registration.referenceToFrame);
  if (!(registration.motionResidual < kClearlyLowerResidual * registration.identityResidual)) {
    registration.motionRejected = true;  // maxShiftPx keeps the shift it would have made
    registration.referenceToFrame = identity;
  }
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

// Dense flow after the homography is taken when it lowers the frame's residual by more than
// this many codes of featureImage and by more than this share of it (a pan the homography
// explains leaves resampling noise, which flow would fit too).
constexpr double kFlowGainCodes = 0.5;
constexpr double kFlowGainFraction = 0.10;
// Forward-backward flow disagreement above which a pixel counts as occluded or mismatched
// (forwardBackwardConsistent): 1 px plus a tenth of the flow's length. With 1 px alone, a fast
// pan (rb2: heavy rain from a vehicle, 24 px a frame, with parallax) kept 54 % of each frame on
// average, the rest left to holes where DIS's flow on flat wet surfaces is least sure and a
// pixel off costs least; with the tenth, 68 %.
constexpr double kFlowConsistencyPx = 1.0;
constexpr double kFlowConsistencyRelative = 0.1;
// A pixel the flow brings within this many codes of featureImage of the reference's (both rain-
// suppressed) joins the solve; beyond it the flow matched the wrong thing there.
constexpr double kFlowAgreementCodes = 12.0;

// The positions of `points` mapped by the homography h.
cv::Mat2f mapped(const cv::Mat2f& points, const cv::Matx33d& h) {
  cv::Mat2f out;
  cv::perspectiveTransform(points, out, cv::Mat(h));
  return out;
}

// The pixel centres' own coordinates on a grid of `size`.
cv::Mat2f gridPoints(cv::Size size) {
  return landingPoints(cv::Mat2f(size, cv::Vec2f(0, 0)));
}

// Frame k refined by dense flow after its homography h, when the flow explains clearly more
// (`residuals` gets the two residuals either way); empty otherwise.
DenseMotion denseMotion(const cv::Mat& reference, const cv::Mat& frame, const cv::Matx33d& h,
                        cv::DISOpticalFlow& flow, std::pair<double, double>& residuals) {
  const cv::Size size = reference.size();
  cv::Mat warped, covered;
  const int inverse = cv::WARP_INVERSE_MAP;
  cv::warpPerspective(frame, warped, cv::Mat(h), size, cv::INTER_LINEAR | inverse,
                      cv::BORDER_REPLICATE);
  cv::warpPerspective(cv::Mat(frame.size(), CV_8U, cv::Scalar(255)), covered, cv::Mat(h), size,
                      cv::INTER_NEAREST | inverse, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::Mat2f forward, backward;
  flow.calc(reference, warped, forward);
  const cv::Mat2f points = landingPoints(forward);
  cv::Mat1f referenceCodes, warpedCodes;
  reference.convertTo(referenceCodes, CV_32F);
  warped.convertTo(warpedCodes, CV_32F);
  cv::Mat1b flowCovered;
  cv::remap(covered, flowCovered, points, cv::noArray(), cv::INTER_NEAREST, cv::BORDER_CONSTANT,
            cv::Scalar(0));
  flowCovered &= inBounds(points);
  residuals.first = trimmedMeanAbsDifference(referenceCodes, warpedCodes, covered);
  const cv::Mat1f flowCodes = remapCubic(warpedCodes, points);
  residuals.second = trimmedMeanAbsDifference(referenceCodes, flowCodes, flowCovered);
  const double gain = residuals.first - residuals.second;
  if (!(gain > kFlowGainCodes && gain > kFlowGainFraction * residuals.first)) return {};

  flow.calc(warped, reference, backward);
  DenseMotion motion;
  motion.toFrame = mapped(points, h);
  cv::Mat1f difference;
  cv::absdiff(flowCodes, referenceCodes, difference);
  motion.validOnReference = flowCovered & (difference < kFlowAgreementCodes) &
                            forwardBackwardConsistent(forward, backward, points, kFlowConsistencyPx,
                                                      kFlowConsistencyRelative);
  // Back from the frame: its pixel p is q = h^-1 p on the homography-warped grid, which the
  // backward flow takes to q + backward(q) on the reference grid.
  const cv::Mat2f backPoints = landingPoints(backward);
  const cv::Mat1b backConsistent = forwardBackwardConsistent(
      backward, forward, backPoints, kFlowConsistencyPx, kFlowConsistencyRelative);
  const cv::Mat2f onWarped = mapped(gridPoints(frame.size()), h.inv());
  cv::remap(backPoints, motion.toReference, onWarped, cv::noArray(), cv::INTER_LINEAR,
            cv::BORDER_REPLICATE);
  cv::Mat1b consistentThere;
  cv::remap(backConsistent, consistentThere, onWarped, cv::noArray(), cv::INTER_NEAREST,
            cv::BORDER_CONSTANT, cv::Scalar(0));
  motion.validOnFrame = inBounds(onWarped) & consistentThere & inBounds(motion.toReference);
  return motion;
}

// Registration::dense for a registration that keeps its motion.
void refineByFlow(const std::vector<cv::Mat>& features, int reference, Registration& registration) {
  requireDenseFlowSize(features.front().size(), "registering a moving camera's frames");
  registration.dense.assign(features.size(), DenseMotion{});
  const cv::Ptr<cv::DISOpticalFlow> flow = makeDenseFlow();
  double before = 0.0, after = 0.0;
  for (size_t k = 0; k < features.size(); ++k) {
    if (int(k) == reference) continue;
    std::pair<double, double> residuals;
    registration.dense[k] = denseMotion(features[size_t(reference)], features[k],
                                        registration.referenceToFrame[k], *flow, residuals);
    if (registration.dense[k].empty()) continue;
    before += residuals.first;
    after += residuals.second;
  }
  const int refined = registration.denseFrames();
  if (refined == 0) return;
  registration.homographyResidual = before / refined;
  registration.flowResidual = after / refined;
}

}  // namespace

int Registration::denseFrames() const {
  return int(std::count_if(dense.begin(), dense.end(),
                           [](const DenseMotion& motion) { return !motion.empty(); }));
}

Registration registerFrames(const std::vector<cv::Mat>& frames, int reference, bool denseFlow) {
  Registration registration;
  registration.referenceToFrame.assign(frames.size(), cv::Matx33d::eye());
  // The rain-suppressed images, made once for the stillness test, the features and the residuals.
  std::vector<cv::Mat> features;
  for (const cv::Mat& frame : frames) features.push_back(featureImage(frame));
  if (cameraIsStill(features)) {
    registration.lockedOff = true;
    return registration;
  }
  auto orb = cv::ORB::create(kFeatures);
  std::vector<std::vector<cv::KeyPoint>> keypoints(frames.size());
  std::vector<cv::Mat> descriptors(frames.size());
  for (size_t k = 0; k < frames.size(); ++k)
    orb->detectAndCompute(features[k], cv::noArray(), keypoints[k], descriptors[k]);
  cv::BFMatcher matcher(cv::NORM_HAMMING);
  std::vector<bool> registered(frames.size(), false);
  registered[size_t(reference)] = true;
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
      registration.placedFrames.push_back(int(k));
      continue;
    }
    registration.referenceToFrame[k] = cv::Matx33d(h);
    registered[k] = true;
  }
  // A frame that could not be registered (blank, blurred, too few features) takes the motion of
  // its nearest registered neighbour (the reference, at worst: identity).
  for (int k : registration.placedFrames) {
    int nearest = reference;
    for (int d = 1; d < int(frames.size()); ++d) {
      if (k - d >= 0 && registered[size_t(k - d)]) {
        nearest = k - d;
        break;
      }
      if (k + d < int(frames.size()) && registered[size_t(k + d)]) {
        nearest = k + d;
        break;
      }
    }
    registration.referenceToFrame[size_t(k)] = registration.referenceToFrame[size_t(nearest)];
    registration.placedWith.push_back(nearest);
  }
  for (size_t k = 0; k < frames.size(); ++k)
    registration.maxShiftPx = std::max(
        registration.maxShiftPx, cornerShift(registration.referenceToFrame[k], frames[k].size()));
  if (registration.maxShiftPx < kStaticShiftPx) {
    // The fits only measured noise. Keep the frames exactly as they are.
    std::fill(registration.referenceToFrame.begin(), registration.referenceToFrame.end(),
              cv::Matx33d::eye());
    return registration;
  }
  keepMotionExplaining(features, reference, registration);
  if (denseFlow && registration.moving()) refineByFlow(features, reference, registration);
  return registration;
}

void keepMotionThatExplains(const std::vector<cv::Mat>& frames, int reference,
                            Registration& registration) {
  std::vector<cv::Mat> features;
  for (const cv::Mat& frame : frames) features.push_back(featureImage(frame));
  keepMotionExplaining(features, reference, registration);
}

FrameStack warpToReference(const std::vector<cv::Mat>& frames, const Registration& registration) {
  FrameStack stack;
  if (!registration.moving()) {
    stack.frames = frames;
    return stack;
  }
  for (size_t k = 0; k < frames.size(); ++k) {
    if (k < registration.dense.size() && !registration.dense[k].empty()) {
      stack.frames.push_back(remapCubic(frames[k], registration.dense[k].toFrame));
      stack.valid.push_back(registration.dense[k].validOnReference.clone());
      continue;
    }
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
  if (size_t(index) < registration.dense.size() && !registration.dense[size_t(index)].empty()) {
    const DenseMotion& motion = registration.dense[size_t(index)];
    cv::Mat warped;
    cv::remap(onReference, warped, motion.toReference, cv::noArray(), cv::INTER_LINEAR,
              cv::BORDER_CONSTANT, cv::Scalar::all(0));
    warped.setTo(cv::Scalar::all(0), ~motion.validOnFrame);
    if (covered) *covered = motion.validOnFrame.clone();
    return warped;
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
