#pragma once
// `pluvia report lights`: error against run time of the local-light approximations, each
// against its brute-force reference:
//  - "halo": a point light's in-scattered radiance from the F(u, v) table
//    (optics::inscatteredRadiance) against the ray marched numerically
//    (optics::inscatteredRadianceReference), per table resolution;
//  - "beam": the same for spotlights (the S and C tables, the lit intervals of the cone);
//  - "drops": a drop lit by a small disc light through the binned transfer table D(theta) (what
//    the rain stage uses per streak, per bin count) against the Monte-Carlo drop tracer
//    (optics/drop_trace.h) lit by the same disc;
//  - "glare": the CIE glare kernel as a pyramid of blurs (optics::GlarePyramid) against direct
//    convolution with the true kernel (optics::glareReference), per frame size; its time is per
//    pixel of a frame.
// Relative error of one sample: |estimate - reference| / reference; a row's mean and max are
// over its samples (random lights, rays, ray lengths and extinctions, fixed seed).
#include <string>
#include <vector>

namespace pluvia::lab {

struct LightsReportSettings {
  int samples = 400;        // (light, ray) pairs per halo and beam row
  int dropAngles = 24;      // scattering angles of the drops rows
  int traceRays = 1 << 20;  // rays of the drop tracer per angle
  bool quick = false;       // fewer samples (tests)
};

struct LightsReportRow {
  std::string group;    // "halo", "beam", "drops", "reference"
  std::string setting;  // "table 128x128", "512 bins"
  double meanRelativeError = 0.0;
  double maxRelativeError = 0.0;
  double nanosecondsPerEvaluation = 0.0;
};

struct LightsReport {
  std::vector<LightsReportRow> rows;
  std::vector<std::string> notes;
};

LightsReport runLightsReport(const LightsReportSettings& settings);
std::string formatLightsReport(const LightsReport& report);
void writeLightsReportCsv(const LightsReport& report, const std::string& path);
// Log-log scatter of mean relative error against time per evaluation, one point per row.
void writeLightsReportPlot(const LightsReport& report, const std::string& path);

}  // namespace pluvia::lab
