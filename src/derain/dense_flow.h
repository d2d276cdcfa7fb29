#pragma once
// Dense optical flow between two rain-suppressed greys, the pieces clean plates (clean_plate.h)
// and derain's registration (registration.h) share: where the reference's pixels land in a
// neighbour, whether the flow there is forward-backward consistent, and the residual the flow is
// judged by.
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

namespace pluvia::derain {

// The mean |a - b| over `mask` (CV_32F greys, CV_8U mask), with the largest 10 % left out: camera
// motion moves every pixel, while a moving object (or rain the suppression left) moves a few;
// their differences, the largest, would let them buy the flow, which then follows the object
// instead of masking it. Not the median either: on a mostly flat scene it does not see a sub-pixel
// shift of the textured part. +infinity when the mask is empty.
double trimmedMeanAbsDifference(const cv::Mat1f& a, const cv::Mat1f& b, const cv::Mat1b& mask);

// Where each pixel x of the reference lands in the neighbour: x + flow(x).
cv::Mat2f landingPoints(const cv::Mat2f& flow);

// 255 where the point lies inside an image of the points' size.
cv::Mat1b inBounds(const cv::Mat2f& points);

// 255 where following the forward flow f to `points` (landingPoints(forward)) and then the
// backward one b returns close to where it started, |f + b|^2 < relative^2 (|f|^2 + |b|^2) +
// tolerancePx^2: occluded and mismatched pixels fail it. The relative part is Sundaram, Brox and
// Keutzer's (ECCV 2010: relative 0.1, tolerance 0.71 px): a long flow's error grows with it.
cv::Mat1b forwardBackwardConsistent(const cv::Mat2f& forward, const cv::Mat2f& backward,
                                    const cv::Mat2f& points, double tolerancePx, double relative);

// An image resampled at `points` (cubic: linear interpolation at half-pixel offsets blurs fine
// texture by several codes), the border replicated.
cv::Mat remapCubic(const cv::Mat& image, const cv::Mat2f& points);

// OpenCV's DIS measures no flow on a frame under 12 px on both sides (it asserts).
inline constexpr int kDenseFlowMinSidePx = 12;
bool denseFlowMeasures(cv::Size frameSize);
// Throws pluvia::Error, "`what` needs frames of at least 12 px on a side to follow their motion,
// and these are WxH px", for a size denseFlowMeasures refuses.
void requireDenseFlowSize(cv::Size frameSize, const std::string& what);

// The flow estimator both use: DIS, PRESET_MEDIUM (multi-scale, so it follows shifts of tens of
// pixels).
cv::Ptr<cv::DISOpticalFlow> makeDenseFlow();

}  // namespace pluvia::derain
