// `pluvia report realism --quick` end to end on the real NTURain clip (skipped without the shared
// data): the real rain's statistics and a preset's, their ratios and typical factor, the CSV,
// the plot and the contact sheet; and a clip that cannot be read is an error naming it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

TEST(CliReportRealism, QuickReportMeasuresRealRainAndAPreset) {
  if (sharedData().empty()) GTEST_SKIP() << "no ../shared/data";
  const auto dir = freshTempDir("report_realism");
  const stdfs::path images = dir / "sheets";
  const QuickReport report =
      runQuickReport(dir, "realism",
                     {"-p", "heavy", "--images", images.string(), "--data", sharedData().string()});
  const CommandResult& r = report.result;
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const CsvTable& table = report.table;
  ASSERT_TRUE(hasColumns(
      table, {"clip", "preset", "typical", "coverage", "delta_p99", "streaks_per_mpx",
              "length_p50_px", "peak_p90", "angle_deg", "ratio_coverage", "ratio_peakP90"}));
  ASSERT_EQ(table.rows.size(), 2u) << r.output;  // real, heavy
  std::map<std::string, size_t> column = table.column;
  const auto value = [&](size_t row, const std::string& name) {
    return parseNumber(table.rows[row][column[name]], table.lines[row]);
  };
  EXPECT_EQ(table.rows[0][column["preset"]], "real");
  EXPECT_EQ(table.rows[0][column["clip"]], "nturain_ra1_real_rain_panning");
  // NTURain's rain is visible and falls nearly vertically (its streaks lean under 10 deg).
  EXPECT_GT(value(0, "coverage"), 0.001);
  EXPECT_GT(value(0, "streaks_per_mpx"), 100.0);
  EXPECT_LT(std::abs(value(0, "angle_deg")), 10.0);
  // The preset's row: its ratios are its statistics over the real ones.
  EXPECT_EQ(table.rows[1][column["preset"]], "heavy");
  EXPECT_NEAR(value(1, "ratio_coverage"), value(1, "coverage") / value(0, "coverage"), 1e-3);
  EXPECT_GE(value(1, "typical"), 1.0);
  expectPlot(report.plot);
  EXPECT_TRUE(stdfs::exists(images / "nturain_ra1_real_rain_panning_sheet.png")) << r.output;
}

TEST(CliReportRealism, AClipThatCannotBeReadIsNamed) {
  const auto dir = freshTempDir("report_realism_missing");
  const stdfs::path missing = dir / "no_such_clip.mp4";
  const CommandResult r =
      runPluvia({"report", "realism", missing.string(), "-p", "heavy", "--quick"});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  expectOutputHas(r.output, {"no_such_clip.mp4"});
}
