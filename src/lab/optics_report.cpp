#include "lab/optics_report.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <stdexcept>

#include <fmt/format.h>

#include "lab/report_numbers.h"
#include "optics/drop_shading.h"
#include "optics/drop_trace.h"
#include "optics/paper_transfer_table.h"
#include "util/error.h"
#include "util/parallel.h"

namespace pluvia::lab {

using namespace pluvia::optics;  // what this file measures
namespace {

using Rgb = std::array<double, 3>;
using Direction = std::array<double, 3>;
using Shader = std::function<Rgb(const Direction&)>;
using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double relativeError(const Rgb& estimate, const Rgb& reference) {
  double sum = 0.0;
  for (size_t c = 0; c < 3; ++c) {
    sum += std::abs(estimate[c] - reference[c]) / std::max(reference[c], 1e-12);
  }
  return sum / 3.0;
}

// Per-drop time: all directions, repeated until at least 30 ms have passed.
double nanosecondsPerDrop(const Shader& shade, const std::vector<Direction>& directions) {
  double checksum = 0.0;
  int64_t evaluations = 0;
  const auto start = Clock::now();
  do {
    for (const Direction& d : directions) checksum += shade(d)[0];
    evaluations += int64_t(directions.size());
  } while (millisecondsSince(start) < 30.0);
  // Using the results keeps the calls from being optimised away, and checks them.
  if (!std::isfinite(checksum)) throw std::runtime_error("non-finite drop radiance while timing");
  return millisecondsSince(start) * 1e6 / double(evaluations);
}

struct Measured {
  double mean = 0.0, max = 0.0;
};

Measured errorsAgainst(const Shader& shade, const std::vector<Direction>& directions,
                       const std::vector<Rgb>& reference) {
  Measured m;
  for (size_t i = 0; i < directions.size(); ++i) {
    const double e = relativeError(shade(directions[i]), reference[i]);
    m.mean += e / double(directions.size());
    m.max = std::max(m.max, e);
  }
  return m;
}

std::vector<Rgb> traceAll(const EquirectMap& environment, const std::vector<Direction>& directions,
                          const Rgb& eta, int samples, uint64_t seed) {
  std::vector<Rgb> out(directions.size());
  TraceSettings trace;
  trace.samples = samples;
  trace.seed = seed;
  forEachIndex(directions.size(), [&](size_t i) {
    out[i] = traceDropRadiance(environment, directions[i], eta, trace);
  });
  return out;
}

class ReportBuilder {
 public:
  ReportBuilder(const EquirectMap& environment, const OpticsReportSettings& settings)
      : environment_(environment),
        settings_(settings),
        directions_(fibonacciDirections(settings.directions)) {
    reference_ = traceAll(environment, directions_, settings.eta, settings.referenceSamples, 1);
  }

  void add(const std::string& group, const std::string& setting, const Shader& shade,
           double precomputeMs, double memoryBytes) {
    const Measured m = errorsAgainst(shade, directions_, reference_);
    report_.rows.push_back({group, setting, m.mean, m.max, nanosecondsPerDrop(shade, directions_),
                            precomputeMs, memoryBytes});
  }

  void addRadianceMap(const std::string& group, int width, int terms) {
    const auto start = Clock::now();
    RadianceMapSettings map;
    map.outputWidth = width;
    map.inputWidth = 2 * width;
    const EquirectMap radiance =
        buildDropRadianceMap(environment_, channelOptics(settings_.eta, terms), map);
    const double ms = millisecondsSince(start);
    add(
        group, fmt::format("radiance map {}x{}, N={}", width, width / 2, terms),
        [&](const Direction& d) {
          const auto c = sampleEquirect(radiance, float(d[0]), float(d[1]), float(d[2]));
          return Rgb{c[0], c[1], c[2]};
        },
        ms, double(radiance.rgb.size() * sizeof(float)));
  }

  void addSh(const std::string& group, const std::string& setting, int order, int terms, double c,
             ShWindow window) {
    const auto start = Clock::now();
    PaperShading sh = preparePaperShading(environment_, settings_.eta, order, terms, window);
    sh.backgroundWeight = c;
    const double ms = millisecondsSince(start);
    const double bytes = double((order + 1) * (order + 1) * 3 + (order + 1) * 3) * sizeof(float);
    add(
        group, setting, [&](const Direction& d) { return shadePaper(sh, environment_, d); }, ms,
        bytes);
  }

  void addPaperTable() {
    const auto start = Clock::now();
    const PaperShading paper = preparePaperShading(environment_, settings_.eta);
    const PaperTransferTable table(paper.zonal);
    const double ms = millisecondsSince(start);
    add(
        "paper", fmt::format("paper table ({} directions), L=3, N=9, c=0.7", table.directions()),
        [&](const Direction& d) {
          Rgb rgb = table.shade(paper.environmentSh, d);
          const auto b = sampleEquirect(environment_, float(d[0]), float(d[1]), float(d[2]));
          for (size_t c = 0; c < 3; ++c)
            rgb[c] = std::max(rgb[c], 0.0) + kPaperBackgroundWeight * b[c];
          return rgb;
        },
        ms, double(table.bytes()));
  }

  void addReference() {
    // The reference against a second run of itself with another seed: its noise.
    const size_t subset = std::min<size_t>(32, directions_.size());
    const std::vector<Direction> some(directions_.begin(), directions_.begin() + long(subset));
    const std::vector<Rgb> again =
        traceAll(environment_, some, settings_.eta, settings_.referenceSamples, 2);
    double noise = 0.0;
    for (size_t i = 0; i < subset; ++i)
      noise += relativeError(again[i], reference_[i]) / double(subset);
    report_.referenceNoise = noise / std::sqrt(2.0);

    TraceSettings trace;  // the reference at its default quality
    const auto start = Clock::now();
    const size_t timed = std::min<size_t>(8, directions_.size());
    for (size_t i = 0; i < timed; ++i)
      traceDropRadiance(environment_, directions_[i], settings_.eta, trace);
    const double ns = millisecondsSince(start) * 1e6 / double(timed);
    report_.rows.push_back(
        {"reference", fmt::format("trace, {} rays (default quality)", trace.samples),
         report_.referenceNoise, 0.0, ns, 0.0, double(environment_.rgb.size() * sizeof(float))});
  }

  OpticsReport finish() {
    report_.directions = int(directions_.size());
    report_.referenceSamples = settings_.referenceSamples;
    return report_;
  }

 private:
  const EquirectMap& environment_;
  OpticsReportSettings settings_;
  std::vector<Direction> directions_;
  std::vector<Rgb> reference_;
  OpticsReport report_;
};

}  // namespace

std::vector<std::array<double, 3>> fibonacciDirections(int count) {
  std::vector<std::array<double, 3>> out;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double y = 1.0 - 2.0 * (i + 0.5) / count;
    const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
    out.push_back({r * std::cos(golden * i), y, r * std::sin(golden * i)});
  }
  return out;
}

OpticsReport runOpticsReport(const EquirectMap& environment, const OpticsReportSettings& settings) {
  if (settings.directions < 1 || settings.referenceSamples < 1 || settings.maxTerms < 1 ||
      settings.maxOrder < 1) {
    throw std::invalid_argument("optics report: directions, samples, terms and order must be >= 1");
  }
  ReportBuilder builder(environment, settings);
  builder.addReference();
  const int defaultWidth = RadianceMapSettings{}.outputWidth;
  for (int width : {64, 128, 256}) {
    builder.addRadianceMap(width == defaultWidth ? "default" : "map size", width, kDefaultTerms);
  }
  for (int terms = 1; terms <= settings.maxTerms; ++terms)
    builder.addRadianceMap("terms", defaultWidth, terms);
  for (int order = 1; order <= settings.maxOrder; ++order) {
    builder.addSh("sh", fmt::format("SH L={}, N={}, closed-form rotation", order, kDefaultTerms),
                  order, kDefaultTerms, 0.0, ShWindow::None);
  }
  builder.addSh("sh", fmt::format("SH L={}, N={}, Hann window", settings.maxOrder, kDefaultTerms),
                settings.maxOrder, kDefaultTerms, 0.0, ShWindow::Hann);
  builder.addSh("paper", "paper: SH L=3, N=9, c=0.7, closed-form rotation", kPaperShOrder,
                kPaperTerms, kPaperBackgroundWeight, ShWindow::None);
  builder.addPaperTable();
  return builder.finish();
}

std::string formatOpticsReport(const OpticsReport& report) {
  std::string out = fmt::format(
      "Drop shading against the Monte-Carlo reference: {} view directions, {} rays each "
      "(reference noise {:.2f} %: the reference row's mean error is that noise).\n",
      report.directions, report.referenceSamples, 100.0 * report.referenceNoise);
  out += fmt::format("{:<10} {:<52} {:>10} {:>10} {:>12} {:>13} {:>12}\n", "group", "setting",
                     "mean err %", "max err %", "ns / drop", "precompute ms", "memory KiB");
  for (const OpticsReportRow& row : report.rows) {
    out +=
        fmt::format("{:<10} {:<52} {:>10.2f} {:>10.2f} {:>12.1f} {:>13.1f} {:>12.1f}\n", row.group,
                    row.setting, 100.0 * row.meanRelativeError, 100.0 * row.maxRelativeError,
                    row.nanosecondsPerDrop, row.precomputeMilliseconds, row.memoryBytes / 1024.0);
  }
  return out;
}

void writeOpticsReportCsv(const OpticsReport& report, const std::string& path) {
  writeReportCsv(
      path,
      "group,setting,mean_relative_error,max_relative_error,ns_per_drop,precompute_ms,memory_"
      "bytes",
      [&](std::ostream& file) {
        for (const OpticsReportRow& row : report.rows) {
          file << fmt::format("{},\"{}\",{:.6g},{:.6g},{:.6g},{:.6g},{:.0f}\n", row.group,
                              row.setting, row.meanRelativeError, row.maxRelativeError,
                              row.nanosecondsPerDrop, row.precomputeMilliseconds, row.memoryBytes);
        }
      });
}

}  // namespace pluvia::lab
