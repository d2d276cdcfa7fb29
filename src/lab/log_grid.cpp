#include "lab/log_grid.h"

#include <cmath>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

namespace pluvia::lab {
namespace {

struct Tick {
  double value;
  bool decade;
};

std::vector<Tick> logTicks(double log10Lo, double log10Hi) {
  std::vector<Tick> ticks;
  for (int decade = int(std::floor(log10Lo)); decade <= int(std::ceil(log10Hi)); ++decade)
    for (double m : {1.0, 2.0, 5.0}) {
      const double value = m * std::pow(10.0, decade), log = std::log10(value);
      if (log >= log10Lo - 1e-9 && log <= log10Hi + 1e-9) ticks.push_back({value, m == 1.0});
    }
  return ticks;
}

cv::Scalar gridColour(bool decade) {
  return decade ? cv::Scalar(215, 215, 215) : cv::Scalar(238, 238, 238);
}

}  // namespace

void drawLogGridX(cv::Mat& canvas, const cv::Rect& plot, double log10Lo, double log10Hi,
                  const std::function<int(double)>& pixelX) {
  for (const Tick& tick : logTicks(log10Lo, log10Hi)) {
    const int px = pixelX(tick.value);
    cv::line(canvas, {px, plot.y}, {px, plot.y + plot.height}, gridColour(tick.decade));
    cv::putText(canvas, fmt::format("{:g}", tick.value), {px - 12, plot.y + plot.height + 25},
                cv::FONT_HERSHEY_SIMPLEX, 0.5, {0, 0, 0});
  }
}

void drawLogGridY(cv::Mat& canvas, const cv::Rect& plot, double log10Lo, double log10Hi,
                  const std::function<int(double)>& pixelY,
                  const std::function<std::string(double)>& label, int labelX) {
  for (const Tick& tick : logTicks(log10Lo, log10Hi)) {
    const int py = pixelY(tick.value);
    cv::line(canvas, {plot.x, py}, {plot.x + plot.width, py}, gridColour(tick.decade));
    cv::putText(canvas, label(tick.value), {labelX, py + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.5,
                {0, 0, 0});
  }
}

}  // namespace pluvia::lab
