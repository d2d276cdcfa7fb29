// The optics report as a picture: mean relative error (log) against time per drop (log), one
// labelled point per row, coloured by group.
#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "lab/optics_report.h"
#include "lab/plot_labels.h"
#include "util/error.h"

namespace pluvia::lab {
namespace {

constexpr int kWidth = 1400, kHeight = 900;
constexpr int kLeft = 110, kRight = 40, kTop = 60, kBottom = 90;

const std::map<std::string, cv::Scalar> kGroupColours = {
    {"default", {40, 160, 40}}, {"map size", {120, 200, 120}}, {"terms", {200, 140, 60}},
    {"sh", {200, 60, 60}},      {"paper", {40, 40, 220}},      {"reference", {0, 0, 0}}};

struct Axis {
  double lo, hi;  // log10
  double fraction(double value) const { return (std::log10(value) - lo) / (hi - lo); }
};

Axis axisFor(const std::vector<double>& values) {
  double lo = 1e300, hi = -1e300;
  for (double v : values) {
    if (v > 0.0) lo = std::min(lo, std::log10(v)), hi = std::max(hi, std::log10(v));
  }
  return {std::floor(lo), std::ceil(hi) + (std::ceil(hi) == std::floor(lo) ? 1.0 : 0.0)};
}

}  // namespace

void writeOpticsReportPlot(const OpticsReport& report, const std::string& path) {
  cv::Mat canvas(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  std::vector<double> times, errors;
  for (const auto& row : report.rows) {
    times.push_back(row.nanosecondsPerDrop);
    errors.push_back(std::max(row.meanRelativeError, 1e-5));
  }
  const Axis x = axisFor(times), y = axisFor(errors);
  const int plotW = kWidth - kLeft - kRight, plotH = kHeight - kTop - kBottom;
  auto toPixel = [&](double t, double e) {
    return cv::Point(kLeft + int(x.fraction(t) * plotW), kTop + plotH - int(y.fraction(e) * plotH));
  };
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  for (int decade = int(x.lo); decade <= int(x.hi); ++decade) {
    const int px = kLeft + int((decade - x.lo) / (x.hi - x.lo) * plotW);
    cv::line(canvas, {px, kTop}, {px, kTop + plotH}, {225, 225, 225});
    cv::putText(canvas, fmt::format("1e{}", decade), {px - 18, kTop + plotH + 25}, font, 0.5,
                {0, 0, 0});
  }
  for (int decade = int(y.lo); decade <= int(y.hi); ++decade) {
    const int py = kTop + plotH - int((decade - y.lo) / (y.hi - y.lo) * plotH);
    cv::line(canvas, {kLeft, py}, {kLeft + plotW, py}, {225, 225, 225});
    cv::putText(canvas, fmt::format("{:g} %", 100.0 * std::pow(10.0, decade)), {10, py + 5}, font,
                0.5, {0, 0, 0});
  }
  cv::rectangle(canvas, {kLeft, kTop}, {kLeft + plotW, kTop + plotH}, {0, 0, 0});
  cv::putText(canvas, "time per drop (ns, log)", {kLeft + plotW / 2 - 100, kHeight - 30}, font, 0.6,
              {0, 0, 0});
  cv::putText(
      canvas,
      fmt::format("Drop shading: mean relative error vs time ({} directions, reference {} rays)",
                  report.directions, report.referenceSamples),
      {kLeft, 35}, font, 0.7, {0, 0, 0}, 2);
  double allTermsError = 0.0;  // the error of the "terms" row with the most terms
  for (const auto& row : report.rows) {
    if (row.group == "terms") allTermsError = row.meanRelativeError;
  }
  PlotLabeller labels(0.38, 7);
  for (const auto& row : report.rows) {
    const cv::Scalar colour =
        kGroupColours.count(row.group) ? kGroupColours.at(row.group) : cv::Scalar(0, 0, 0);
    const cv::Point p = toPixel(row.nanosecondsPerDrop, std::max(row.meanRelativeError, 1e-5));
    cv::circle(canvas, p, 5, colour, cv::FILLED);
    // The "terms" sweep is labelled by N alone, and only where its points still spread out.
    std::string label = row.setting;
    if (row.group == "terms") {
      label = label.substr(label.find("N="));
      if (row.meanRelativeError < 2.0 * allTermsError) continue;
    }
    labels.draw(canvas, p, label, colour);
  }
  int legendY = kTop + 20;
  for (const auto& [group, colour] : kGroupColours) {
    cv::circle(canvas, {kLeft + plotW - 150, legendY - 4}, 5, colour, cv::FILLED);
    cv::putText(canvas, group, {kLeft + plotW - 138, legendY}, font, 0.5, colour);
    legendY += 20;
  }
  if (!cv::imwrite(path, canvas))
    throw Error("cannot write the plot (is it a .png path?)", {"report", {}, path});
}

}  // namespace pluvia::lab
