#include "lab/fog_report.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <random>

#include "optics/skylight_scattering.h"

namespace pluvia::lab {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kPathsMeters[] = {5.0, 300.0, 5000.0};

// References per (direction, path), computed once per environment.
struct Sample {
  std::array<double, 3> view;
  double pathMeters;
  std::array<double, 3> reference;
};

template <typename Model>
void score(const std::vector<Sample>& samples, double sigma, Model model, FogReportRow& row) {
  int n = 0;
  for (const Sample& s : samples) {
    const std::array<float, 3> in = model(s.view);
    const double alpha = 1.0 - std::exp(-sigma * s.pathMeters);
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
      const double r = s.reference[size_t(c)];
      if (r > 0.0) worst = std::max(worst, std::abs(in[size_t(c)] * alpha - r) / r);
    }
    row.meanRelativeError += worst;
    row.maxRelativeError = std::max(row.maxRelativeError, worst);
    ++n;
  }
  row.meanRelativeError /= std::max(n, 1);
}

}  // namespace

std::vector<FogReportRow> runFogReport(
    const std::vector<std::pair<std::string, EquirectMap>>& environments,
    const FogReportSettings& settings) {
  optics::SkylightMedium medium;
  medium.rainExtinctionPerMeter = settings.rainExtinctionPerMeter;
  medium.fogPerMeter = settings.fogPerMeter;
  const double sigma = medium.extinctionPerMeter();
  std::vector<FogReportRow> rows;
  for (const auto& [name, environment] : environments) {
    std::vector<Sample> samples;
    const auto refStart = Clock::now();
    for (const auto& v : randomViewDirections(settings.directions, 11)) {
      for (double path : kPathsMeters)
        samples.push_back({v, path, optics::skylightReference(environment, medium, v, path)});
    }
    FogReportRow reference{
        name, fmt::format("reference ({}x{} texels)", environment.width, environment.height)};
    reference.nanosecondsPerPixel =
        std::chrono::duration<double, std::nano>(Clock::now() - refStart).count() /
        double(samples.size());
    rows.push_back(reference);
    for (int width : {8, 16, 32, 64, 128, 256}) {
      FogReportRow row{name, fmt::format("skylight {}x{}", width, width / 2)};
      const auto start = Clock::now();
      const optics::SkylightTable table = optics::buildSkylightTable(environment, width);
      row.buildMilliseconds =
          std::chrono::duration<double, std::milli>(Clock::now() - start).count();
      // Per-pixel cost: the table lookup and mix, timed over many evaluations.
      const auto views = randomViewDirections(4096, 11);
      float sink = 0.0f;
      const auto evalStart = Clock::now();
      for (int repeat = 0; repeat < 64; ++repeat)
        for (const auto& v : views) sink += optics::skylightInscatter(table, medium, v)[0];
      row.nanosecondsPerPixel =
          std::chrono::duration<double, std::nano>(Clock::now() - evalStart).count() /
              (64.0 * double(views.size())) +
          0.0 * sink;
      score(
          samples, sigma,
          [&](const std::array<double, 3>& v) {
            return optics::skylightInscatter(table, medium, v);
          },
          row);
      rows.push_back(row);
    }
    // The exponential model's airlight: the sky at the horizon (elevations 0 to 10 deg), as the
    // lighting stage's Environment::horizonRgb, at the same extinction.
    FogReportRow exponential{name, "exponential (horizon)"};
    const std::array<float, 3> horizon = equirectBandMean(environment, 0.0, 10.0);
    score(
        samples, sigma, [&](const std::array<double, 3>&) { return horizon; }, exponential);
    rows.push_back(exponential);
  }
  return rows;
}

std::string formatFogReport(const std::vector<FogReportRow>& rows) {
  std::string out = fmt::format("{:<28} {:<26} {:>10} {:>10} {:>10} {:>10}\n", "environment",
                                "model", "mean err", "max err", "build ms", "ns/pixel");
  for (const FogReportRow& r : rows) {
    out += fmt::format("{:<28} {:<26} {:>9.3f}% {:>9.3f}% {:>10.1f} {:>10.1f}\n", r.environment,
                       r.model, 100.0 * r.meanRelativeError, 100.0 * r.maxRelativeError,
                       r.buildMilliseconds, r.nanosecondsPerPixel);
  }
  return out;
}

std::vector<std::array<double, 3>> randomViewDirections(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<std::array<double, 3>> out;
  for (int i = 0; i < count; ++i) {
    std::array<double, 3> v{g(rng), g(rng), g(rng)};
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (double& c : v) c /= n;
    out.push_back(v);
  }
  return out;
}

}  // namespace pluvia::lab
