// A night plate's lamp through the shipped `heavy` at its defaults, the rain off so that only
// the grading stages (wet ground, darken, blur, fog) touch the frame: the lamp's clipped core and
// its glow come out as the plate holds them, and the dark street around is graded
// (stages/lamp_keeping.h). On the real night clip of a street lamp they turned the core's 1.0
// into 0.945 and took 19 % off its glow.
#include <gtest/gtest.h>

#include <cmath>

#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr double kLampX = 160.0, kLampY = 190.0;  // low in the frame, where the guessed ground is

// Display-referred: a dark street (code 0.15) with the lamp's clipped core (radius 10 px) in a
// glow fading over 40 px.
float plateValue(int x, int y) {
  const double d = std::hypot(x + 0.5 - kLampX, y + 0.5 - kLampY);
  return d <= 10 ? 1.0f : std::max(0.15f, float(0.95 / (1.0 + std::pow((d - 10) / 14, 2))));
}

}  // namespace

TEST(CliNightLampGrading, TheGradingLeavesALampAndItsGlowAsThePlateHoldsThem) {
  const stdfs::path dir = freshTempDir("night_lamp_grading");
  const std::string plate =
      writePixelPlate(dir, 1, 1, kWidth, kHeight,
                      [](float* p, int x, int y, int) { p[0] = p[1] = p[2] = plateValue(x, y); });
  const stdfs::path out = dir / "graded.####.exr", kept = dir / "plate.####.exr";
  const auto rendered = runPluvia(
      {"render", plate, "-p", "heavy", "--set", "rain.enabled=false", "-o", out.string()});
  ASSERT_EQ(rendered.exitCode, 0) << rendered.output;
  expectOutputHas(rendered.output,
                  {"runs", "wet_ground", "darken", "fog",
                   "grading: a night plate: the lamps in their own glows are kept"});
  // The plate in the working space, every stage off: the reference.
  const auto passed =
      runPluvia({"-q", "render", plate, "-p", "heavy", "--set", "rain.enabled=false", "--set",
                 "wet_ground.enabled=false", "--set", "darken.enabled=false", "--set",
                 "blur.enabled=false", "--set", "fog.enabled=false", "-o", kept.string()});
  ASSERT_EQ(passed.exitCode, 0) << passed.output;
  const Image graded = readImageFile(dir / "graded.0001.exr");
  const Image before = readImageFile(dir / "plate.0001.exr");
  ASSERT_EQ(graded.width, kWidth);
  // The core and the glow (at 5, 20 and 25 px: 1.0, 0.63 and 0.44 in display codes; nine tenths
  // of its light over the street's has faded 27 px out).
  for (const double r : {0.0, 5.0, 20.0, 25.0}) {
    const int x = int(kLampX + r), y = int(kLampY);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(graded.pixel(x, y)[c], before.pixel(x, y)[c], 1e-4) << "at " << r << " px";
  }
  EXPECT_NEAR(graded.pixel(int(kLampX), int(kLampY))[1], 1.0f, 1e-4);
  // The dark street far from the lamp is graded: darker, by more than a per cent.
  const float street = before.pixel(40, 225)[1];
  EXPECT_LT(graded.pixel(40, 225)[1], 0.99f * street) << "street " << street;
}
