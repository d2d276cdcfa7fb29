// `pluvia report derain --quick` end to end: the table it prints, its CSV (median and solver rows
// with finite numbers; the solver's background better than the median's), its plot and previews.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

TEST(CliReportDerain, QuickReportWritesCsvPlotAndPreviews) {
  const auto dir = freshTempDir("report_derain");
  const stdfs::path images = dir / "images";
  const QuickReport report = runQuickReport(dir, "derain", {"--images", images.string()});
  const CommandResult& r = report.result;
  ASSERT_EQ(r.exitCode, 0) << r.output;

  // Printed rows: the lines that start with a section name.
  const int printedRows =
      countLinesStartingWith(r.output, {"synthetic", "moving", "iterations", "window"});

  const CsvTable& table = report.table;
  ASSERT_TRUE(hasColumns(table, {"section", "method", "frames", "psnr_db", "ssim", "alpha_mae",
                                 "angle_deg", "angle_error_deg", "seconds"}));
  std::map<std::string, size_t> column = table.column;
  double medianPsnr = NAN, solverPsnr = NAN;
  std::map<std::string, double> movingPsnr;
  for (size_t row = 0; row < table.rows.size(); ++row) {
    const std::vector<std::string>& fields = table.rows[row];
    const std::string& line = table.lines[row];
    const std::string& method = fields[column["method"]];
    // Real footage rows (none in --quick) have no ground truth, so no measures.
    if (fields[column["section"]] == "real") continue;
    // The moving camera's rows are measured against the middle frame's clean image only.
    if (fields[column["section"]] == "moving") {
      movingPsnr[method] = parseNumber(fields[column["psnr_db"]], line);
      continue;
    }
    if (method != "median" && method != "solver") continue;
    // Every measure of a median or solver row is a finite number.
    expectFiniteMeasures(
        table, row,
        {"frames", "psnr_db", "ssim", "alpha_mae", "angle_deg", "angle_error_deg", "seconds"},
        false);
    const double ssim = parseNumber(fields[column["ssim"]], line);
    EXPECT_GT(ssim, 0.0) << line;
    EXPECT_LE(ssim, 1.0) << line;
    const double alphaError = parseNumber(fields[column["alpha_mae"]], line);
    EXPECT_GE(alphaError, 0.0) << line;
    EXPECT_LE(alphaError, 1.0) << line;
    if (fields[column["section"]] == "synthetic") {
      (method == "median" ? medianPsnr : solverPsnr) = parseNumber(fields[column["psnr_db"]], line);
    }
  }
  EXPECT_EQ(int(table.rows.size()), printedRows) << r.output;
  ASSERT_TRUE(std::isfinite(medianPsnr)) << "no synthetic median row";
  ASSERT_TRUE(std::isfinite(solverPsnr)) << "no synthetic solver row";
  // Eq. (1) over 20 frames recovers the background at least 1 dB better than the per-pixel
  // median (the target).
  EXPECT_GE(solverPsnr, medianPsnr + 1.0) << "(the table is printed above)";
  // With parallax the default (dense flow after the homography) is within 3 dB of the
  // flow-registered median and far above the homography alone, which ghosts the near layer.
  ASSERT_EQ(movingPsnr.size(), 4u) << r.output;
  EXPECT_GE(movingPsnr["default"], movingPsnr["median"] - 3.0) << r.output;
  EXPECT_GE(movingPsnr["default"], movingPsnr["homography"] + 6.0) << r.output;

  expectPlot(report.plot);
  for (const char* name : {"synthetic_truth.png", "synthetic_median.png", "synthetic_solver.png",
                           "synthetic_matte_solver_x4.png", "moving_default.png"}) {
    EXPECT_TRUE(stdfs::exists(images / name)) << name;
  }
}

TEST(CliReportDerain, RejectsAMissingDataFolder) {
  expectReportRejectsMissing("derain", "--data", freshTempDir("report_derain_errors") / "missing");
}

}  // namespace
