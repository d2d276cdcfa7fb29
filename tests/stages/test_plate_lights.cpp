// Which plates lights.find auto treats as night (isNightPlate): the luminance quantiles worked
// by hand on synthetic plates, and the real weir photo of ../shared/data (a sunny day, mostly in
// shade), whose clipped white railing must not be taken for lamps.
#include <gtest/gtest.h>

#include <cmath>

#include "night_plate.h"
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

namespace {

// A night plate (0.02) with a clipped disc of radius 3 px at (x, y) inside a glow of its own
// (luminance 0.95 / (1 + (d / 5 px)^2), over 0.4 of the clip level at the rim) or inside a lit
// wall (a 40 px square at 0.6 around it).
Image lampPlate(bool glow, int x0, int y0) {
  Image image = test::flatImage(160, 120, 0.02f, 0.02f, 0.02f);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const double d = std::hypot(x + 0.5 - x0, y + 0.5 - y0);
      float v = 0.02f;
      if (glow) v = std::max(v, float(0.95 / (1.0 + (d / 5.0) * (d / 5.0))));
      if (!glow && std::abs(x - x0) < 20 && std::abs(y - y0) < 20) v = 0.6f;
      if (d <= 3.0) v = 1.0f;
      std::fill(image.pixel(x, y), image.pixel(x, y) + 3, v);
    }
  return image;
}

}  // namespace

// A street lamp filmed at night is a clipped core inside its own glow: its rim is bright (it
// failed the old test, a dark rim, and a real night clip's lamp was "0 lights found"), its
// surround dark. A clipped patch on a lit wall has a bright surround and stays no lamp.
TEST(PlateLights, ALampInItsOwnGlowIsFoundALitWallIsNot) {
  const Camera camera = Camera::fromFieldOfView(160, 120, 50, 0, 1.6);
  LightsSettings settings;
  const std::vector<PlateBlob> glowing = findClippedBlobs(lampPlate(true, 80, 40), 0.95, 4);
  ASSERT_EQ(glowing.size(), 1u);
  EXPECT_GT(glowing[0].rimLuminance, 0.4 * 0.95);  // the old test's dark rim fails
  EXPECT_LT(glowing[0].surroundLuminance, 0.2 * 0.95);
  const std::vector<FoundLamp> lamps =
      findPlateLamps(lampPlate(true, 80, 40), settings, camera, nullptr, 20.0);
  ASSERT_EQ(lamps.size(), 1u);
  EXPECT_NEAR(lamps[0].xPx, 80.0, 0.5);
  EXPECT_NEAR(lamps[0].yPx, 40.0, 0.5);
  // Its disc is its glow's clipped centre: at the clip level, not find_core_gain times it.
  const double solidAngle = lamps[0].areaPx / (camera.focalPx * camera.focalPx);
  const Eigen::Vector3d ray = camera.rayCamera(lamps[0].xPx, lamps[0].yPx) * 20.0;
  EXPECT_NEAR(lamps[0].intensity, 0.95 * solidAngle * ray.squaredNorm(), 1e-6 * lamps[0].intensity);
  EXPECT_TRUE(findPlateLamps(lampPlate(false, 80, 40), settings, camera, nullptr, 20.0).empty());
}

// A lamp close to the camera: a clipped core of radius 12 px in a glow fading over 30 px, which
// fills a fifth of the frame with light over 0.3. The glow is the lamp's, not the scene's: the
// plate is a night one. The same light spread flat over the frame's top (a sunlit strip holding a
// clipped patch as big as the core) is a day plate.
TEST(PlateLights, ALampsOwnGlowDoesNotMakeANightPlateDay) {
  const Image lamp = test::lampInItsGlow(12.0);
  int lit = 0;
  for (size_t i = 0; i < lamp.pixelCount(); ++i) lit += lamp.rgba[i * 4] >= 0.3f;
  ASSERT_GT(lit, int(lamp.pixelCount() / 10));  // the brightest tenth is glow
  EXPECT_TRUE(isNight(lamp));
  EXPECT_LT(plateLuminance(lamp).upperTenth, 0.3);

  Image strip = plate(0.02f, 24, 0.5f);  // a fifth of the rows at 0.5
  for (int y = 0; y < 8; ++y)
    for (int x = 70; x < 130; ++x) std::fill(strip.pixel(x, y), strip.pixel(x, y) + 3, 1.0f);
  EXPECT_FALSE(isNight(strip));
}
