#pragma once
// `pluvia report optics`: error against run time of every drop-shading approximation, each
// measured against the Monte-Carlo reference (drop_trace.h) over a Fibonacci set of view
// directions in one environment.
//
// Relative error of one direction: the mean over R, G, B of |estimate - reference| /
// reference. A row's mean and max are over the directions. Time per evaluation is the
// per-drop cost once the method's per-environment precomputation is done; that one-off cost is
// its own column, as is the memory kept per environment.
#include <array>
#include <string>
#include <vector>

#include "image/equirect.h"

namespace pluvia::lab {

struct OpticsReportSettings {
  int directions = 256;
  int referenceSamples = 65536;  // rays per direction of the reference
  int maxTerms = 20;             // rows N = 1..maxTerms
  int maxOrder = 8;              // rows L = 1..maxOrder
  std::array<double, 3> eta = {1.333, 1.333, 1.333};
};

struct OpticsReportRow {
  std::string group;    // "default", "terms", "sh", "paper", "reference"
  std::string setting;  // e.g. "radiance map 128x64, N=20"
  double meanRelativeError = 0.0;
  double maxRelativeError = 0.0;
  double nanosecondsPerDrop = 0.0;
  double precomputeMilliseconds = 0.0;
  double memoryBytes = 0.0;
};

struct OpticsReport {
  std::vector<OpticsReportRow> rows;
  int directions = 0;
  int referenceSamples = 0;
  // Mean relative difference between two reference runs with different seeds, divided by
  // sqrt(2): the noise of one reference value, the floor below which errors are not resolved.
  double referenceNoise = 0.0;
};

OpticsReport runOpticsReport(const EquirectMap& environment, const OpticsReportSettings& settings);

std::string formatOpticsReport(const OpticsReport& report);
void writeOpticsReportCsv(const OpticsReport& report, const std::string& path);
// Log-log scatter of mean relative error against time per drop, one labelled point per row.
void writeOpticsReportPlot(const OpticsReport& report, const std::string& path);

// The unit directions of a Fibonacci sphere: evenly spread, deterministic.
std::vector<std::array<double, 3>> fibonacciDirections(int count);

}  // namespace pluvia::lab
