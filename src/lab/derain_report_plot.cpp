// The derain report as a picture: PSNR of S against run time (log), the EM-iteration sweep and
// the window sweep as lines, the median baseline as markers. Same canvas, margins, fonts and
// grid as the optics report's plot.
#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "lab/derain_report.h"
#include "lab/log_grid.h"
#include "lab/plot_labels.h"
#include "util/error.h"

namespace pluvia::lab {

using namespace pluvia::derain;  // what this file measures
namespace {

constexpr int kWidth = 1400, kHeight = 900;
constexpr int kLeft = 110, kRight = 40, kTop = 60, kBottom = 90;
constexpr int kPlotW = kWidth - kLeft - kRight, kPlotH = kHeight - kTop - kBottom;
const auto kFont = cv::FONT_HERSHEY_SIMPLEX;

const cv::Scalar kIterationColour{200, 140, 60};  // BGR
const cv::Scalar kWindowColour{40, 160, 40};
const cv::Scalar kMedianColour{40, 40, 220};

struct Point {
  double seconds, psnr;
  std::string label;
};

struct Axes {
  double logLo, logHi;  // time, log10 seconds
  double lo, hi;        // PSNR, dB
  cv::Point at(double seconds, double psnr) const {
    const double fx = (std::log10(seconds) - logLo) / (logHi - logLo);
    const double fy = (psnr - lo) / (hi - lo);
    return {kLeft + int(std::lround(fx * kPlotW)), kTop + kPlotH - int(std::lround(fy * kPlotH))};
  }
};

void drawSeries(cv::Mat& canvas, const Axes& axes, const std::vector<Point>& points,
                const cv::Scalar& colour, bool joined, PlotLabeller& labels) {
  for (size_t i = 0; joined && i + 1 < points.size(); ++i) {
    cv::line(canvas, axes.at(points[i].seconds, points[i].psnr),
             axes.at(points[i + 1].seconds, points[i + 1].psnr), colour, 2, cv::LINE_AA);
  }
  for (const Point& p : points) {
    const cv::Point at = axes.at(p.seconds, p.psnr);
    if (joined) {
      cv::circle(canvas, at, 5, colour, cv::FILLED, cv::LINE_AA);
    } else {
      cv::drawMarker(canvas, at, colour, cv::MARKER_DIAMOND, 14, 2, cv::LINE_AA);
    }
    labels.draw(canvas, at, p.label, colour);
  }
}

}  // namespace

void writeDerainReportPlot(const DerainReport& report, const std::string& path) {
  std::vector<Point> iterations, windows, medians;
  std::string scene;
  double angle = 0.0;
  for (const DerainReportRow& row : report.rows) {
    if (row.section == "iterations") {
      iterations.push_back({row.seconds, row.psnrDb, fmt::format("{} it", row.iterations)});
      scene = row.scene;
      angle = row.trueAngleDeg;
    } else if (row.section == "window" && row.method == "solver") {
      windows.push_back({row.seconds, row.psnrDb, fmt::format("{} frames", row.frames)});
    } else if (row.section == "window" && row.method == "median") {
      medians.push_back({row.seconds, row.psnrDb, fmt::format("median, {} frames", row.frames)});
    }
  }

  double tLo = 1e300, tHi = -1e300, pLo = 1e300, pHi = -1e300;
  for (const auto* series : {&iterations, &windows, &medians}) {
    for (const Point& p : *series) {
      if (!(p.seconds > 0.0) || !std::isfinite(p.psnr)) continue;
      tLo = std::min(tLo, p.seconds), tHi = std::max(tHi, p.seconds);
      pLo = std::min(pLo, p.psnr), pHi = std::max(pHi, p.psnr);
    }
  }
  if (tLo > tHi) throw Error("the derain report has no sweep to plot", {"report", {}, path});
  const Axes axes{std::log10(tLo) - 0.15, std::log10(tHi) + 0.15, std::floor(pLo - 0.5),
                  std::ceil(pHi + 0.5)};

  cv::Mat canvas(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  // Time grid: 1, 2, 5 per decade.
  drawLogGridX(canvas, cv::Rect(kLeft, kTop, kPlotW, kPlotH), axes.logLo, axes.logHi,
               [&](double t) { return axes.at(t, axes.lo).x; });
  // PSNR grid: a step of 1, 2 or 5 dB giving at most 12 lines.
  double step = 1.0;
  for (double s : {1.0, 2.0, 5.0, 10.0}) {
    step = s;
    if ((axes.hi - axes.lo) / s <= 12.0) break;
  }
  for (double v = std::ceil(axes.lo / step) * step; v <= axes.hi + 1e-9; v += step) {
    const int py = axes.at(1.0 * std::pow(10.0, axes.logLo), v).y;
    cv::line(canvas, {kLeft, py}, {kLeft + kPlotW, py}, {225, 225, 225});
    cv::putText(canvas, fmt::format("{:g} dB", v), {30, py + 5}, kFont, 0.5, {0, 0, 0});
  }
  cv::rectangle(canvas, {kLeft, kTop}, {kLeft + kPlotW, kTop + kPlotH}, {0, 0, 0});
  cv::putText(canvas, "run time per stack (s, log)", {kLeft + kPlotW / 2 - 110, kHeight - 30},
              kFont, 0.6, {0, 0, 0});
  cv::putText(canvas,
              fmt::format("Rain extraction: PSNR of the background vs run time ({}, rain at {:g} "
                          "deg, {}x{}, display encoding)",
                          scene, angle, report.size.width, report.size.height),
              {kLeft, 35}, kFont, 0.7, {0, 0, 0}, 2);

  PlotLabeller labels(0.42, 8);
  drawSeries(canvas, axes, iterations, kIterationColour, true, labels);
  drawSeries(canvas, axes, windows, kWindowColour, true, labels);
  drawSeries(canvas, axes, medians, kMedianColour, false, labels);

  const std::pair<const char*, cv::Scalar> legend[] = {
      {"EM iterations (full window, tolerance 0)", kIterationColour},
      {"window size (default settings)", kWindowColour},
      {"temporal median baseline", kMedianColour}};
  int legendY = kTop + kPlotH - 70;
  for (const auto& [text, colour] : legend) {
    cv::circle(canvas, {kLeft + kPlotW - 380, legendY - 4}, 5, colour, cv::FILLED, cv::LINE_AA);
    cv::putText(canvas, text, {kLeft + kPlotW - 368, legendY}, kFont, 0.5, colour);
    legendY += 22;
  }
  if (!cv::imwrite(path, canvas))
    throw Error("cannot write the plot (is it a .png path?)", {"report", {}, path});
}

}  // namespace pluvia::lab
