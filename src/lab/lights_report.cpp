#include "lab/lights_report.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "image/equirect.h"
#include "lab/halo_frame_rows.h"
#include "lab/report_numbers.h"
#include "optics/drop_trace.h"
#include "optics/drop_transfer.h"
#include "optics/glare.h"
#include "optics/single_scattering.h"
#include "util/error.h"
#include "util/hash.h"
#include "util/timer.h"

namespace pluvia::lab {
namespace {

using optics::Vec3;

struct Case {
  optics::LocalLight light;
  Vec3 ray;
  double lengthMeters;
  double beta;
};

Vec3 unit(Vec3 v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}

// Lights within 30 m ahead of the camera (some behind), rays in the frame of a 60 deg lens
// aimed near the light, half of them to the sky (infinite), extinction from light rain to fog.
std::vector<Case> makeCases(int count, bool spots, uint64_t seed) {
  CounterRng rng(seed, spots ? 2 : 1);
  std::vector<Case> cases;
  while (int(cases.size()) < count) {
    Case c;
    c.light.positionMeters = {rng.uniform() * 16 - 8, rng.uniform() * 8 - 2,
                              -1.0 - rng.uniform() * 30.0 + (rng.uniform() < 0.1 ? 10.0 : 0.0)};
    c.light.radiusMeters = 0.05;
    const Vec3 toLight = unit(c.light.positionMeters);
    c.ray = unit({toLight[0] + rng.uniform() * 0.6 - 0.3, toLight[1] + rng.uniform() * 0.6 - 0.3,
                  toLight[2] - 0.2});
    c.lengthMeters = rng.uniform() < 0.5 ? HUGE_VAL : 1.0 + rng.uniform() * 40.0;
    c.beta = std::exp(std::log(0.003) + rng.uniform() * std::log(0.5 / 0.003));
    if (spots) {
      c.light.spot = true;
      c.light.axis = unit({rng.uniform() * 2 - 1, -rng.uniform(), rng.uniform() * 2 - 1});
      c.light.cosHalfAngle = std::cos((2.0 + rng.uniform() * 78.0) * M_PI / 180.0);
      c.light.falloffQ = rng.uniform();
    }
    // Samples whose reference is negligible against the brightest the light gives are left out
    // (relative error of nothing).
    if (optics::inscatteredRadianceReference(c.light, c.ray, c.lengthMeters, c.beta) < 1e-9)
      continue;
    cases.push_back(c);
  }
  return cases;
}

void scatteringRows(LightsReport& report, const LightsReportSettings& settings, bool spots) {
  const std::vector<Case> cases = makeCases(settings.samples, spots, 18);
  std::vector<double> reference;
  auto started = std::chrono::steady_clock::now();
  for (const Case& c : cases)
    reference.push_back(
        optics::inscatteredRadianceReference(c.light, c.ray, c.lengthMeters, c.beta));
  const double referenceNs = 1e9 * secondsSince(started) / double(cases.size());
  const std::string group = spots ? "beam" : "halo";
  for (int size : {16, 32, 64, 128, 256}) {
    const optics::ScatteringTables tables(size, size);
    LightsReportRow row{group, fmt::format("table {}x{}", size, size)};
    std::vector<double> estimate(cases.size());
    constexpr int kRepeats = 5;
    started = std::chrono::steady_clock::now();
    for (int k = 0; k < kRepeats; ++k)
      for (size_t i = 0; i < cases.size(); ++i)
        estimate[i] = optics::inscatteredRadiance(tables, cases[i].light, cases[i].ray,
                                                  cases[i].lengthMeters, cases[i].beta);
    row.nanosecondsPerEvaluation = 1e9 * secondsSince(started) / double(kRepeats * cases.size());
    for (size_t i = 0; i < cases.size(); ++i) {
      const double e = std::abs(estimate[i] - reference[i]) / reference[i];
      row.meanRelativeError += e / double(cases.size());
      row.maxRelativeError = std::max(row.maxRelativeError, e);
    }
    report.rows.push_back(row);
  }
  report.rows.push_back({"reference", group + ": ray marched", 0.0, 0.0, referenceNs});
}

// A disc light of angular radius kDiscDeg straight up (+Y), radiance chosen so that it gives an
// irradiance of 1 at normal incidence: the drop's radiance is then the mean of D over the disc.
constexpr double kDiscDeg = 4.0;

EquirectMap discLight(int width) {
  EquirectMap map(width, width / 2);
  const double cosDisc = std::cos(kDiscDeg * M_PI / 180.0);
  const double solidAngle = 2.0 * M_PI * (1.0 - cosDisc);
  for (int y = 0; y < map.height; ++y) {
    const double polar = (y + 0.5) / map.height * M_PI;  // from +Y
    if (std::cos(polar) < cosDisc) continue;
    for (int x = 0; x < map.width; ++x)
      for (int c = 0; c < 3; ++c) map.texel(x, y)[c] = float(1.0 / solidAngle);
  }
  return map;
}

// The table's mean over the disc seen from view v: sampled on a polar grid over the disc.
double tableOverDisc(const optics::TransferTable& table, const Vec3& view) {
  constexpr int kRings = 24, kSpokes = 48;
  const double radius = kDiscDeg * M_PI / 180.0;
  double sum = 0.0, weight = 0.0;
  for (int i = 0; i < kRings; ++i) {
    const double t = (i + 0.5) / kRings * radius;
    for (int j = 0; j < kSpokes; ++j) {
      const double phi = (j + 0.5) / kSpokes * 2.0 * M_PI;
      const Vec3 w{std::sin(t) * std::cos(phi), std::cos(t), std::sin(t) * std::sin(phi)};
      const double mu = -(view[0] * w[0] + view[1] * w[1] + view[2] * w[2]);
      sum += table.at(mu) * std::sin(t);
      weight += std::sin(t);
    }
  }
  return sum / weight;
}

void dropRows(LightsReport& report, const LightsReportSettings& settings) {
  // The disc's own edge must be resolved by the map: about 10 texels across its radius.
  const EquirectMap light = discLight(2048);
  optics::TraceSettings trace;
  trace.samples = settings.traceRays;
  std::vector<Vec3> views;
  std::vector<double> reference;
  // Scattering angles from 20 to 170 deg between the view and the light.
  for (int k = 0; k < settings.dropAngles; ++k) {
    const double scatter = (20.0 + 150.0 * (k + 0.5) / settings.dropAngles) * M_PI / 180.0;
    // v = camera -> drop; w = drop -> light = +Y; angle(v, w) is the table's theta, and the
    // tracer's view direction is v.
    const Vec3 v{std::sin(scatter), std::cos(scatter), 0.0};
    views.push_back(v);
    reference.push_back(optics::traceDropRadiance(light, v, {1.333, 1.333, 1.333}, trace)[1]);
  }
  for (int bins : {64, 128, 256, 512, 1024}) {
    const optics::TransferTable table = optics::binTransfer(optics::DropOptics{}, bins);
    LightsReportRow row{"drops", fmt::format("{} bins", bins)};
    int kept = 0;
    for (size_t i = 0; i < views.size(); ++i) {
      if (!(reference[i] > 0.0)) continue;
      // D(angle(v, w)) in the table's convention: mu = cos(theta) with w the light's direction.
      const Vec3 v = views[i];
      const double estimate = tableOverDisc(table, {-v[0], -v[1], -v[2]});
      const double e = std::abs(estimate - reference[i]) / reference[i];
      row.meanRelativeError += e;
      row.maxRelativeError = std::max(row.maxRelativeError, e);
      ++kept;
    }
    row.meanRelativeError /= std::max(kept, 1);
    const auto started = std::chrono::steady_clock::now();
    double sink = 0.0;
    constexpr int kLookups = 1000000;
    for (int k = 0; k < kLookups; ++k) sink += table.at(-1.0 + 2.0 * (k + 0.5) / kLookups);
    row.nanosecondsPerEvaluation = 1e9 * secondsSince(started) / kLookups + (sink < 0 ? 1 : 0);
    report.rows.push_back(row);
  }
  report.notes.push_back(fmt::format(
      "drops: a {:g} deg disc light of unit irradiance; the table is averaged over the disc as the "
      "tracer sees it, so the rows measure the table and the closed-form D against the tracer "
      "({} rays per angle, {} angles from 20 to 170 deg)",
      kDiscDeg, trace.samples, settings.dropAngles));
}

// Glare: the pyramid (optics::GlarePyramid) against direct convolution with the true CIE kernel
// (optics::glareReference, by FFT) on a frame of a 60 deg lens with a few coloured point
// sources; relative error of the output per pixel and channel, away from the sources' own
// pixels (3 px), where the unscattered light dominates; time per pixel of a frame.
void glareRows(LightsReport& report, const LightsReportSettings& settings) {
  std::vector<std::pair<int, int>> sizes{{480, 270}};
  if (!settings.quick) sizes.push_back({960, 540});
  for (const auto& [width, height] : sizes) {
    const double focalPx = 0.5 * width / std::tan(M_PI / 6.0);
    Image source(width, height);
    std::fill(source.rgba.begin(), source.rgba.end(), 0.0f);
    CounterRng rng(18, 3);
    std::vector<std::array<int, 2>> at;
    for (int k = 0; k < 6; ++k) {
      const int x = int(rng.uniform() * width), y = int(rng.uniform() * height);
      at.push_back({x, y});
      for (int c = 0; c < 3; ++c)
        source.pixel(x, y)[c] = float(std::pow(10.0, 1.0 + 3.0 * rng.uniform()));
    }
    auto started = std::chrono::steady_clock::now();
    const optics::GlarePyramid pyramid(width, height, focalPx);
    const double fitSeconds = secondsSince(started);
    Image fast;
    constexpr int kRepeats = 3;
    started = std::chrono::steady_clock::now();
    for (int k = 0; k < kRepeats; ++k) fast = pyramid.convolve(source);
    const double pixels = double(width) * height;
    const double fastNs = 1e9 * secondsSince(started) / kRepeats / pixels;
    started = std::chrono::steady_clock::now();
    const Image reference = optics::glareReference(source, focalPx);
    const double referenceNs = 1e9 * secondsSince(started) / pixels;
    LightsReportRow row{"glare", fmt::format("pyramid {}x{}", width, height)};
    int n = 0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        bool nearSource = false;
        for (const auto& p : at) nearSource = nearSource || std::hypot(x - p[0], y - p[1]) < 3.0;
        if (nearSource) continue;
        for (int c = 0; c < 3; ++c) {
          const double ref = reference.pixel(x, y)[c];
          if (!(ref > 0.0)) continue;
          const double e = std::abs(fast.pixel(x, y)[c] - ref) / ref;
          row.meanRelativeError += e;
          row.maxRelativeError = std::max(row.maxRelativeError, e);
          ++n;
        }
      }
    row.meanRelativeError /= std::max(n, 1);
    row.nanosecondsPerEvaluation = fastNs;
    report.rows.push_back(row);
    report.rows.push_back(
        {"reference", fmt::format("glare: FFT {}x{}", width, height), 0.0, 0.0, referenceNs});
    report.notes.push_back(fmt::format(
        "glare {}x{}: CIE 2002 disability glare PSF (age 25, p 0.5) as {} pyramid levels; it "
        "scatters {:.1f} % of a source's light within half the frame's diagonal, the fit {:.1f} "
        "%; fit {:.0f} ms once, {:.1f} ms a frame ({:.0f} ms direct); ns/eval per pixel",
        width, height, pyramid.levels(), 100.0 * pyramid.scatteredFraction(),
        100.0 * pyramid.fittedScatteredFraction(), 1e3 * fitSeconds, fastNs * pixels * 1e-6,
        referenceNs * pixels * 1e-6));
  }
}

}  // namespace

LightsReport runLightsReport(const LightsReportSettings& in) {
  LightsReportSettings settings = in;
  if (settings.quick) {
    settings.samples = std::min(settings.samples, 60);
    settings.dropAngles = std::min(settings.dropAngles, 6);
    settings.traceRays = std::min(settings.traceRays, 1 << 16);
  }
  LightsReport report;
  scatteringRows(report, settings, false);
  scatteringRows(report, settings, true);
  dropRows(report, settings);
  glareRows(report, settings);
  addHaloFrameRows(report, settings.quick);
  return report;
}

std::string formatLightsReport(const LightsReport& report) {
  std::string out = fmt::format("{:<10} {:<22} {:>10} {:>10} {:>12}\n", "group", "setting",
                                "mean err %", "max err %", "ns/eval");
  for (const auto& row : report.rows)
    out += fmt::format("{:<10} {:<22} {:>10} {:>10} {:>12.1f}\n", row.group, row.setting,
                       row.group == "reference" ? "-" : percentOrDash(row.meanRelativeError),
                       row.group == "reference" ? "-" : percentOrDash(row.maxRelativeError),
                       row.nanosecondsPerEvaluation);
  for (const auto& note : report.notes) out += "note: " + note + "\n";
  return out;
}

void writeLightsReportCsv(const LightsReport& report, const std::string& path) {
  writeReportCsv(path, "group,setting,mean_relative_error,max_relative_error,ns_per_evaluation",
                 [&](std::ostream& f) {
                   for (const auto& row : report.rows)
                     f << row.group << ",\"" << row.setting << "\","
                       << csvNumber(row.meanRelativeError) << "," << csvNumber(row.maxRelativeError)
                       << "," << csvNumber(row.nanosecondsPerEvaluation) << "\n";
                 });
}

void writeLightsReportPlot(const LightsReport& report, const std::string& path) {
  constexpr int kW = 1000, kH = 700, kLeft = 90, kBottom = 70, kTop = 50, kRight = 30;
  cv::Mat canvas(kH, kW, CV_8UC3, cv::Scalar(255, 255, 255));
  double tLo = 1e300, tHi = -1e300, eLo = 1e300, eHi = -1e300;
  for (const auto& row : report.rows) {
    if (row.group == "reference") continue;
    tLo = std::min(tLo, std::log10(row.nanosecondsPerEvaluation));
    tHi = std::max(tHi, std::log10(row.nanosecondsPerEvaluation));
    const double e = std::log10(std::max(row.meanRelativeError, 1e-6));
    eLo = std::min(eLo, e), eHi = std::max(eHi, e);
  }
  tLo = std::floor(tLo), tHi = std::ceil(tHi) + 0.01, eLo = std::floor(eLo),
  eHi = std::ceil(eHi) + 0.01;
  const int w = kW - kLeft - kRight, h = kH - kTop - kBottom;
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  cv::rectangle(canvas, {kLeft, kTop}, {kLeft + w, kTop + h}, {0, 0, 0});
  for (int d = int(tLo); d <= int(tHi); ++d)
    cv::putText(canvas, fmt::format("1e{} ns", d),
                {kLeft + int((d - tLo) / (tHi - tLo) * w) - 20, kTop + h + 25}, font, 0.45,
                {0, 0, 0});
  for (int d = int(eLo); d <= int(eHi); ++d)
    cv::putText(canvas, fmt::format("{:g} %", 100.0 * std::pow(10.0, d)),
                {5, kTop + h - int((d - eLo) / (eHi - eLo) * h) + 5}, font, 0.45, {0, 0, 0});
  // The 5 % line the issue asks each approximation to be under.
  const int y5 = kTop + h - int((std::log10(0.05) - eLo) / (eHi - eLo) * h);
  if (y5 > kTop && y5 < kTop + h) cv::line(canvas, {kLeft, y5}, {kLeft + w, y5}, {0, 0, 200});
  cv::putText(canvas, "Local lights: mean relative error vs time per evaluation", {kLeft, 30}, font,
              0.6, {0, 0, 0}, 2);
  for (const auto& row : report.rows) {
    if (row.group == "reference") continue;
    const cv::Scalar colour = row.group == "halo"    ? cv::Scalar(40, 160, 40)
                              : row.group == "beam"  ? cv::Scalar(200, 100, 40)
                              : row.group == "glare" ? cv::Scalar(160, 40, 160)
                                                     : cv::Scalar(40, 40, 200);
    const cv::Point p(
        kLeft + int((std::log10(row.nanosecondsPerEvaluation) - tLo) / (tHi - tLo) * w),
        kTop + h -
            int((std::log10(std::max(row.meanRelativeError, 1e-6)) - eLo) / (eHi - eLo) * h));
    cv::circle(canvas, p, 5, colour, cv::FILLED);
    cv::putText(canvas, row.group + " " + row.setting, {p.x + 7, p.y - 4}, font, 0.38, colour);
  }
  if (!cv::imwrite(path, canvas))
    throw Error(fmt::format("cannot write {}", path), {"report", {}, path});
}

}  // namespace pluvia::lab
