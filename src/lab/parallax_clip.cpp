#include "lab/parallax_clip.h"

#include <opencv2/core.hpp>

#include "util/error.h"

namespace pluvia::lab {
namespace {

// `layer` moved left by `shiftPx` (whole pixels), its edges reflected.
cv::Mat shiftedLeft(const cv::Mat& layer, int shiftPx) {
  cv::Mat padded;
  const int margin = std::abs(shiftPx);
  cv::copyMakeBorder(layer, padded, 0, 0, margin, margin, cv::BORDER_REFLECT);
  return padded(cv::Rect(margin + shiftPx, 0, layer.cols, layer.rows)).clone();
}

}  // namespace

std::vector<cv::Mat> makeParallaxClip(const cv::Mat& photo, cv::Size size,
                                      const ParallaxClipSettings& settings) {
  if (photo.type() != CV_32FC3 || photo.cols < size.width || photo.rows < size.height ||
      settings.frames < 1 || settings.pillarWidthPx < 1 ||
      settings.pillarSpacingPx <= settings.pillarWidthPx)
    throw Error("parallax clip: a CV_32FC3 photo at least the clip's size, and valid settings");
  const cv::Rect middle((photo.cols - size.width) / 2, (photo.rows - size.height) / 2, size.width,
                        size.height);
  const cv::Mat far = photo(middle).clone();
  cv::Mat near;
  cv::flip(far, near, -1);
  near *= 0.6;
  cv::Mat1b pillars(size, uchar(0));
  for (int x = 0; x < size.width; x += settings.pillarSpacingPx)
    pillars.colRange(x, std::min(size.width, x + settings.pillarWidthPx)).setTo(255);
  std::vector<cv::Mat> frames;
  const int centre = settings.frames / 2;
  for (int k = 0; k < settings.frames; ++k) {
    const int t = k - centre;
    cv::Mat frame = shiftedLeft(far, settings.farShiftPxPerFrame * t);
    shiftedLeft(near, settings.nearShiftPxPerFrame * t)
        .copyTo(frame, shiftedLeft(pillars, settings.nearShiftPxPerFrame * t));
    frames.push_back(frame);
  }
  return frames;
}

}  // namespace pluvia::lab
