// `pluvia strokes` end to end. On real panning rain footage (NTURain ra1, 20 frames) it cuts a
// library of at least 20 strokes at the rain's own angle. The angle it reports (the derain's,
// from the mattes' spectrum) is checked against an independent measurement: the streaks of the
// real rain layer, frame minus a registered temporal median clean plate (lab/real_rain_clip.h),
// whose elongated ridges give their own mean angle (the statistics of `pluvia report realism`).
// On the example plate, which shows walkers and no rain, it cuts fewer than 20 and says that a
// library so small repeats.
#include <cmath>
#include <regex>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "lab/real_rain_clip.h"
#include "test_support.h"
#include "util/fs.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

size_t strokesIn(const stdfs::path& library) {
  return nlohmann::json::parse(fs::readTextFile(library))["strokes"].size();
}

}  // namespace

TEST(CliStrokes, RealPanningRainGivesALibraryAtTheStreaksOwnAngle) {
  if (sharedData().empty()) GTEST_SKIP() << "../shared/data absent";
  const std::string clip =
      (sharedData() / "rain_real" / "nturain_ra1_real_rain_panning" / "%05d.jpg").string();
  const auto dir = freshTempDir("strokes_real");
  const CommandResult r =
      runPluvia({"strokes", clip, "-o", (dir / "lib.json").string(), "--frames", "1-20"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_GE(strokesIn(dir / "lib.json"), 20u) << r.output;
  EXPECT_TRUE(stdfs::exists(dir / "lib.png"));
  std::smatch found;
  ASSERT_TRUE(std::regex_search(r.output, found,
                                std::regex("rain angle ([-0-9.]+) deg \\(found in 1 of 1 windows")))
      << r.output;
  const double strokesAngleDeg = std::stod(found[1]);

  // The real layer's streaks, measured at 640 px wide over the same frames (measured: 0.1 deg
  // against the strokes' -1.4 deg).
  const lab::RealClip real = lab::readRealClip(clip, 20, 640);
  const derain::StreakStats streaks =
      lab::measureLayers(real.frames, lab::cleanPlatesRgb(real.frames));
  EXPECT_NEAR(strokesAngleDeg, streaks.angleDeg, 3.0) << r.output;
  EXPECT_LT(std::abs(strokesAngleDeg), 5.0) << "NTURain ra1 falls near-vertically";
}

TEST(CliStrokes, FootageWithoutRainCutsASmallLibraryAndSaysItRepeats) {
  const auto dir = freshTempDir("strokes_dry");
  const CommandResult r = runPluvia(
      {"strokes", exampleClip().string(), "-o", (dir / "lib.json").string(), "--frames", "0-9"});
  if (r.exitCode == 1) {  // nothing at all: the error names the clip, nothing is written
    expectOutputHas(r.output, {"no rain strokes found", "street_plate.mp4"});
    EXPECT_FALSE(stdfs::exists(dir / "lib.json"));
    return;
  }
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_LT(strokesIn(dir / "lib.json"), 20u) << r.output;
  expectOutputHas(r.output, {"a library this small repeats", "street_plate.mp4"});
}
