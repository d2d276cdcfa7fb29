// `pluvia report depth`'s plot (depth_report.h).
#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "lab/depth_report.h"
#include "lab/log_grid.h"
#include "lab/report_numbers.h"
#include "util/error.h"

namespace pluvia::lab {

// The plot: same canvas, margins and fonts as the other reports' plots, in two panels.
void writeDepthReportPlot(const DepthReport& report, const std::string& path) {
  constexpr int kWidth = 1400, kHeight = 900;
  constexpr int kTop = 80, kBottom = 90, kPanelW = 560, kPanelH = kHeight - kTop - kBottom;
  const int panelLeft[2] = {110, 110 + kPanelW + 110};
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  const cv::Scalar palette[] = {{200, 140, 60}, {40, 160, 40}, {40, 40, 220}, {160, 60, 160},
                                {0, 140, 200},  {120, 120, 0}, {90, 90, 90},  {200, 60, 60}};
  std::vector<const DepthReportRow*> rows;
  for (const DepthReportRow& row : report.rows)
    if (std::isfinite(row.totalSeconds) && row.totalSeconds > 0.0) rows.push_back(&row);
  if (rows.empty()) throw Error("the depth report has no row to plot", {"report", {}, path});

  double tLo = 1e300, tHi = -1e300;
  for (const DepthReportRow* row : rows)
    tLo = std::min(tLo, row->totalSeconds), tHi = std::max(tHi, row->totalSeconds);
  tHi = std::max(tHi, kDepthReportSecondsTarget);
  const double xLo = std::floor(std::log10(tLo) - 0.1), xHi = std::ceil(std::log10(tHi) + 0.1);

  cv::Mat canvas(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::putText(canvas,
              "SfM (COLMAP) on the synthetic street vs total time (tracking + densifying the clip)",
              {110, 35}, font, 0.7, {0, 0, 0}, 2);
  std::map<std::string, size_t> colourOf;
  for (const DepthReportRow* row : rows) {
    const std::string size = fmt::format("{}x{}", row->width, row->height);
    if (!colourOf.count(size)) colourOf.emplace(size, colourOf.size());
  }

  for (int panel = 0; panel < 2; ++panel) {
    const int left = panelLeft[panel];
    const double target = panel == 0 ? kDepthReportRotationTargetDeg : kDepthReportDepthTarget;
    auto value = [&](const DepthReportRow* row) {
      return panel == 0 ? row->rotationMaxDeg : row->depthMedian;
    };
    double eLo = target, eHi = target;
    for (const DepthReportRow* row : rows) {
      const double e = value(row);
      if (std::isfinite(e) && e > 0.0) eLo = std::min(eLo, e), eHi = std::max(eHi, e);
    }
    const double yLo = std::floor(std::log10(eLo) - 0.1), yHi = std::ceil(std::log10(eHi) + 0.1);
    auto at = [&](double t, double e) {
      const double fx = (std::log10(t) - xLo) / (xHi - xLo);
      const double fy = (std::log10(e) - yLo) / (yHi - yLo);
      return cv::Point(left + int(std::lround(fx * kPanelW)),
                       kTop + kPanelH - int(std::lround(fy * kPanelH)));
    };
    const cv::Rect plot(left, kTop, kPanelW, kPanelH);
    drawLogGridX(canvas, plot, xLo, xHi, [&](double t) { return at(t, std::pow(10.0, yLo)).x; });
    drawLogGridY(
        canvas, plot, yLo, yHi, [&](double e) { return at(std::pow(10.0, xLo), e).y; },
        [&](double e) {
          return panel == 0 ? fmt::format("{:g}", e) : fmt::format("{:g} %", 100.0 * e);
        },
        left - 90);
    const int targetY = at(std::pow(10.0, xLo), target).y;
    cv::line(canvas, {left, targetY}, {left + kPanelW, targetY}, {0, 0, 200}, 1, cv::LINE_AA);
    cv::putText(canvas,
                panel == 0 ? fmt::format("target {:g} deg", target)
                           : fmt::format("target {:g} %", 100.0 * target),
                {left + 6, targetY - 6}, font, 0.5, {0, 0, 200});
    const int timeX = at(kDepthReportSecondsTarget, std::pow(10.0, yLo)).x;
    cv::line(canvas, {timeX, kTop}, {timeX, kTop + kPanelH}, {0, 0, 200}, 1, cv::LINE_AA);
    cv::putText(canvas, "5 min", {timeX + 4, kTop + 15}, font, 0.45, {0, 0, 200});
    cv::rectangle(canvas, {left, kTop}, {left + kPanelW, kTop + kPanelH}, {0, 0, 0});
    cv::putText(
        canvas,
        panel == 0 ? "worst rotation error (deg, log)" : "median relative depth error (log)",
        {left, kTop - 12}, font, 0.6, {0, 0, 0});
    cv::putText(canvas, "total time (s, log)", {left + kPanelW / 2 - 80, kHeight - 30}, font, 0.6,
                {0, 0, 0});
    for (const DepthReportRow* row : rows) {
      const double e = value(row);
      if (!(std::isfinite(e) && e > 0.0)) continue;
      const cv::Scalar colour =
          palette[colourOf[fmt::format("{}x{}", row->width, row->height)] % std::size(palette)];
      const cv::Point p = at(row->totalSeconds, e);
      cv::circle(canvas, p, 5, colour, cv::FILLED, cv::LINE_AA);
      cv::putText(canvas, fmt::format("{}/{}", row->framesUsed, row->clipFrames),
                  {p.x + 8, p.y - 6}, font, 0.42, colour);
    }
  }
  int legendY = kTop + kPanelH - 30 - 22 * static_cast<int>(colourOf.size());
  for (const auto& [name, index] : colourOf) {
    const cv::Scalar colour = palette[index % std::size(palette)];
    cv::circle(canvas, {panelLeft[1] + kPanelW - 130, legendY - 4}, 5, colour, cv::FILLED,
               cv::LINE_AA);
    cv::putText(canvas, name, {panelLeft[1] + kPanelW - 118, legendY}, font, 0.5, colour);
    legendY += 22;
  }
  cv::putText(canvas, "labels: frames to COLMAP / clip frames",
              {panelLeft[1] + kPanelW - 330, legendY}, font, 0.45, {0, 0, 0});
  if (!cv::imwrite(path, canvas))
    throw Error("cannot write the plot (is it a .png path?)", {"report", {}, path});
}

}  // namespace pluvia::lab
