#pragma once
// Point labels on the reports' plots, placed so that they do not overlap.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace pluvia::lab {

// Each label goes right of its point (left of it where it would leave the canvas) and is pushed
// down until it overlaps no label drawn before it.
class PlotLabeller {
 public:
  // Text in cv::FONT_HERSHEY_SIMPLEX at `fontScale`, `gapPx` from its point.
  PlotLabeller(double fontScale, int gapPx) : fontScale_(fontScale), gapPx_(gapPx) {}
  void draw(cv::Mat& canvas, cv::Point p, const std::string& text, const cv::Scalar& colour);

 private:
  double fontScale_;
  int gapPx_;
  std::vector<cv::Rect> placed_;
};

}  // namespace pluvia::lab
