#pragma once
// Grid lines of a log-scaled plot axis (the reports' error-against-time plots): at 1, 2 and 5
// times each power of ten within the axis, darker at the powers of ten, each labelled.
#include <functional>
#include <string>

#include <opencv2/core.hpp>

namespace pluvia::lab {

// Vertical lines across `plot` at the values whose log10 lies in [log10Lo, log10Hi]; `pixelX`
// maps a value to its column. Labels ("{:g}") go under the plot.
void drawLogGridX(cv::Mat& canvas, const cv::Rect& plot, double log10Lo, double log10Hi,
                  const std::function<int(double)>& pixelX);

// Horizontal lines likewise; `pixelY` maps a value to its row, `label` writes it at column
// `labelX`.
void drawLogGridY(cv::Mat& canvas, const cv::Rect& plot, double log10Lo, double log10Hi,
                  const std::function<int(double)>& pixelY,
                  const std::function<std::string(double)>& label, int labelX);

}  // namespace pluvia::lab
