// Which plates lights.find auto treats as night (isNightPlate): the luminance quantiles worked
// by hand on synthetic plates, and the real weir photo of ../shared/data (a sunny day, mostly in
// shade), whose clipped white railing must not be taken for lamps.
#include <gtest/gtest.h>

#include <cmath>

#include "stages/plate_lights.h"
#include "test_support.h"

using namespace pluvia;

namespace {

// A 100 x 100 plate of grey `dark` with its first `brightRows` rows at grey `bright`.
Image plate(float dark, int brightRows, float bright) {
  Image image = test::flatImage(100, 100, dark, dark, dark);
  for (int y = 0; y < brightRows; ++y)
    for (int x = 0; x < 100; ++x) std::fill(image.pixel(x, y), image.pixel(x, y) + 3, bright);
  return image;
}

float srgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

bool isNight(const Image& image) {
  return isNightPlate(plateLuminance(image));
}

}  // namespace

TEST(PlateLights, LuminanceQuantilesOfATwoLevelPlate) {
  // 20 of 100 rows at 0.5, the rest at 0.02: the median is dark, the 90th percentile bright.
  PlateLuminance luminance = plateLuminance(plate(0.02f, 20, 0.5f));
  EXPECT_FLOAT_EQ(luminance.median, 0.02f);
  EXPECT_FLOAT_EQ(luminance.upperTenth, 0.5f);
  // 9 rows bright: the 90th percentile (the 9000th of 10000 values, counted from 0) still dark.
  luminance = plateLuminance(plate(0.02f, 9, 0.5f));
  EXPECT_FLOAT_EQ(luminance.upperTenth, 0.02f);
}

TEST(PlateLights, NightNeedsADarkMedianAndADarkBrightestTenth) {
  // A dark street with lamps covering 5 % of it: night.
  EXPECT_TRUE(isNight(plate(0.02f, 5, 1.0f)));
  // As dark at the median, but a sunlit fifth: a day plate in shade.
  EXPECT_FALSE(isNight(plate(0.02f, 20, 0.6f)));
  // A bright plate.
  EXPECT_FALSE(isNight(plate(0.2f, 0, 0.0f)));
  // The brightest tenth just under and just over 0.3.
  EXPECT_TRUE(isNight(plate(0.02f, 20, 0.29f)));
  EXPECT_FALSE(isNight(plate(0.02f, 20, 0.31f)));
}

TEST(PlateLights, TheSunnyWeirInShadeIsNotANightPlate) {
  const auto data = test::sharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent";
  Image weir = test::readImageFile(data / "stitching/weir/weir_1.jpg");
  for (size_t i = 0; i < weir.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c) weir.rgba[i * 4 + c] = srgbToLinear(weir.rgba[i * 4 + c]);
  // Dark enough at the median to have passed the median test alone (measured 0.058)...
  EXPECT_LT(plateLuminance(weir).median, 0.08);
  // ...but its sunlit walls and railing make the brightest tenth bright (measured 0.67).
  EXPECT_GT(plateLuminance(weir).upperTenth, 0.5);
  EXPECT_FALSE(isNight(weir));
  // The same photo darkened to 6 % (as the night-light tests darken the street plate) is one.
  for (size_t i = 0; i < weir.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c) weir.rgba[i * 4 + c] *= 0.06f;
  EXPECT_TRUE(isNight(weir));
}
