// `pluvia report envmap`'s plot (envmap_report.h).
#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "lab/envmap_report.h"
#include "lab/log_grid.h"
#include "lab/report_numbers.h"
#include "util/error.h"

namespace pluvia::lab {

// The plot: same canvas, margins and fonts as the other reports' plots.
void writeEnvmapReportPlot(const EnvmapReport& report, const std::string& path) {
  constexpr int kWidth = 1400, kHeight = 900;
  constexpr int kLeft = 110, kRight = 40, kTop = 60, kBottom = 90;
  constexpr int kPlotW = kWidth - kLeft - kRight, kPlotH = kHeight - kTop - kBottom;
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  const cv::Scalar palette[] = {{200, 140, 60}, {40, 160, 40}, {40, 40, 220}, {160, 60, 160},
                                {0, 140, 200},  {120, 120, 0}, {90, 90, 90},  {200, 60, 60}};

  double tLo = 1e300, tHi = -1e300, eLo = 1e300, eHi = -1e300;
  for (const EnvmapReportRow& row : report.rows) {
    const double t = row.placementSeconds + row.renderSeconds, e = row.dropMeanError;
    if (!(t > 0.0) || !(e > 0.0) || !std::isfinite(e)) continue;
    tLo = std::min(tLo, t), tHi = std::max(tHi, t), eLo = std::min(eLo, e), eHi = std::max(eHi, e);
  }
  if (tLo > tHi) throw Error("the envmap report has no row to plot", {"report", {}, path});
  const double xLo = std::floor(std::log10(tLo) - 0.1), xHi = std::ceil(std::log10(tHi) + 0.1);
  const double yLo = std::floor(std::log10(std::min(eLo, kEnvmapDropColourTarget)) - 0.1);
  const double yHi = std::ceil(std::log10(std::max(eHi, kEnvmapDropColourTarget)) + 0.1);
  auto at = [&](double t, double e) {
    const double fx = (std::log10(t) - xLo) / (xHi - xLo), fy = (std::log10(e) - yLo) / (yHi - yLo);
    return cv::Point(kLeft + int(std::lround(fx * kPlotW)),
                     kTop + kPlotH - int(std::lround(fy * kPlotH)));
  };

  cv::Mat canvas(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Rect plot(kLeft, kTop, kPlotW, kPlotH);
  drawLogGridX(canvas, plot, xLo, xHi, [&](double t) { return at(t, std::pow(10.0, yLo)).x; });
  drawLogGridY(
      canvas, plot, yLo, yHi, [&](double e) { return at(std::pow(10.0, xLo), e).y; },
      [](double e) { return fmt::format("{:g} %", 100.0 * e); }, 20);
  const int targetY = at(std::pow(10.0, xLo), kEnvmapDropColourTarget).y;
  cv::line(canvas, {kLeft, targetY}, {kLeft + kPlotW, targetY}, {0, 0, 200}, 1, cv::LINE_AA);
  cv::putText(canvas, "target 10 %", {kLeft + 6, targetY - 6}, font, 0.5, {0, 0, 200});
  cv::rectangle(canvas, {kLeft, kTop}, {kLeft + kPlotW, kTop + kPlotH}, {0, 0, 0});
  cv::putText(canvas, "stitching time: placement + rendering (s, log)",
              {kLeft + kPlotW / 2 - 200, kHeight - 30}, font, 0.6, {0, 0, 0});
  cv::putText(canvas,
              fmt::format("Stitched environment: mean drop colour error in covered directions vs "
                          "time ({}x{} frames, {:g} deg hfov)",
                          report.frameWidth, report.frameHeight, report.horizontalFovDeg),
              {kLeft, 35}, font, 0.7, {0, 0, 0}, 2);

  std::map<std::string, size_t> colourOf;
  std::map<std::string, cv::Point> previous;
  for (const EnvmapReportRow& row : report.rows) {
    const double t = row.placementSeconds + row.renderSeconds, e = row.dropMeanError;
    if (!(t > 0.0) || !(e > 0.0) || !std::isfinite(e)) continue;
    if (!colourOf.count(row.environment)) colourOf.emplace(row.environment, colourOf.size());
    const cv::Scalar colour = palette[colourOf[row.environment] % std::size(palette)];
    const cv::Point p = at(t, e);
    if (row.lightsRestored) {
      cv::drawMarker(canvas, p, colour, cv::MARKER_DIAMOND, 14, 2, cv::LINE_AA);
    } else {
      if (previous.count(row.environment))
        cv::line(canvas, previous[row.environment], p, colour, 2, cv::LINE_AA);
      previous[row.environment] = p;
      cv::circle(canvas, p, 5, colour, cv::FILLED, cv::LINE_AA);
    }
    cv::putText(canvas, envmapRowLabel(row), {p.x + 8, p.y - 6}, font, 0.42, colour);
  }
  int legendY = kTop + 25;
  for (const auto& [name, index] : colourOf) {
    const cv::Scalar colour = palette[index % std::size(palette)];
    cv::circle(canvas, {kLeft + kPlotW - 330, legendY - 4}, 5, colour, cv::FILLED, cv::LINE_AA);
    cv::putText(canvas, name, {kLeft + kPlotW - 318, legendY}, font, 0.5, colour);
    legendY += 22;
  }
  cv::putText(canvas, "diamonds: clipped light sources restored", {kLeft + kPlotW - 330, legendY},
              font, 0.5, {0, 0, 0});
  if (!cv::imwrite(path, canvas))
    throw Error("cannot write the plot (is it a .png path?)", {"report", {}, path});
}

}  // namespace pluvia::lab
