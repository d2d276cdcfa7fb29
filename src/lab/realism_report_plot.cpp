// The realism report as a picture: each preset's ratio to real per statistic, on a log axis from
// x0.1 to x10 with x1 (real) marked, one line per clip and preset.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "lab/log_grid.h"
#include "lab/plot_labels.h"
#include "lab/realism_report.h"
#include "util/error.h"

namespace pluvia::lab {
namespace {

constexpr int kWidth = 1400, kHeight = 900;
constexpr int kLeft = 110, kRight = 220, kTop = 60, kBottom = 90;
constexpr int kPlotW = kWidth - kLeft - kRight, kPlotH = kHeight - kTop - kBottom;
constexpr double kLog10Lo = -1.0, kLog10Hi = 1.0;
const auto kFont = cv::FONT_HERSHEY_SIMPLEX;

cv::Scalar colourOf(size_t i) {
  static const cv::Scalar colours[] = {{200, 140, 60}, {40, 160, 40},  {40, 40, 220},
                                       {180, 60, 180}, {20, 150, 200}, {120, 120, 40},
                                       {90, 90, 90},   {60, 60, 160}};
  return colours[i % std::size(colours)];
}

}  // namespace

void writeRealismReportPlot(const RealismReport& report, const std::string& path) {
  cv::Mat canvas(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Rect plot(kLeft, kTop, kPlotW, kPlotH);
  cv::rectangle(canvas, plot, cv::Scalar(0, 0, 0), 1);
  const auto pixelY = [](double ratio) {
    const double f = (std::log10(std::clamp(ratio, 0.1, 10.0)) - kLog10Lo) / (kLog10Hi - kLog10Lo);
    return kTop + kPlotH - int(std::lround(f * kPlotH));
  };
  drawLogGridY(
      canvas, plot, kLog10Lo, kLog10Hi, pixelY, [](double v) { return fmt::format("x{:g}", v); },
      20);
  cv::line(canvas, {kLeft, pixelY(1.0)}, {kLeft + kPlotW, pixelY(1.0)}, cv::Scalar(0, 0, 0), 2);
  std::vector<std::string> names;
  for (const RealismRow& row : report.rows)
    if (!row.ratios.empty()) {
      for (const auto& [name, ratio] : row.ratios) names.push_back(name);
      break;
    }
  const auto pixelX = [&](size_t i) {
    return kLeft + int((i + 0.5) * kPlotW / std::max<size_t>(1, names.size()));
  };
  for (size_t i = 0; i < names.size(); ++i)
    cv::putText(canvas, names[i], {pixelX(i) - 40, kTop + kPlotH + 30}, kFont, 0.5,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  size_t series = 0;
  PlotLabeller labels(0.5, 8);
  for (const RealismRow& row : report.rows) {
    if (row.ratios.empty()) continue;
    const cv::Scalar colour = colourOf(series++);
    cv::Point last(-1, -1);
    for (size_t i = 0; i < row.ratios.size(); ++i) {
      const double ratio = row.ratios[i].second;
      if (!(ratio > 0.0) || !std::isfinite(ratio)) {
        last = {-1, -1};
        continue;
      }
      const cv::Point at(pixelX(i), pixelY(ratio));
      if (last.x >= 0) cv::line(canvas, last, at, colour, 2, cv::LINE_AA);
      cv::circle(canvas, at, 4, colour, cv::FILLED, cv::LINE_AA);
      last = at;
    }
    if (last.x >= 0)
      labels.draw(canvas, last,
                  fmt::format("{} {} x{:.2f}", row.clip.substr(0, 12), row.preset, row.typical),
                  colour);
  }
  cv::putText(canvas, "pluvia / real rain, per streak statistic (log scale)", {kLeft, 35}, kFont,
              0.8, cv::Scalar(0, 0, 0), 2, cv::LINE_AA);
  if (!cv::imwrite(path, canvas))
    throw Error("cannot write the plot " + path, {"report", {}, path});
}

}  // namespace pluvia::lab
