#include "lab/plot_labels.h"

#include <opencv2/imgproc.hpp>

namespace pluvia::lab {

void PlotLabeller::draw(cv::Mat& canvas, cv::Point p, const std::string& text,
                        const cv::Scalar& colour) {
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, font, fontScale_, 1, &baseline);
  cv::Rect box(p.x + gapPx_, p.y - 4 - size.height, size.width, size.height + baseline);
  if (box.x + box.width > canvas.cols - 5) box.x = p.x - gapPx_ - size.width;
  for (bool clear = false; !clear;) {
    clear = true;
    for (const cv::Rect& other : placed_) {
      if ((box & other).area() > 0) {
        box.y = other.y + other.height + 1;
        clear = false;
      }
    }
  }
  placed_.push_back(box);
  cv::putText(canvas, text, {box.x, box.y + size.height}, font, fontScale_, colour);
}

}  // namespace pluvia::lab
