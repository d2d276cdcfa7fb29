// The lens the plate's files state (pipeline/plate_lens.h): the view from the 35 mm equivalent
// over the picture's diagonal, the sensor width the focal length spans in it, and the preset's
// keys for what is not stated.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "pipeline/plate_lens.h"

using namespace pluvia;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

ClipInfo clipWith(std::map<std::string, std::string> metadata, int width, int height) {
  ClipInfo clip;
  clip.path = "plate.exr";
  clip.width = width;
  clip.height = height;
  clip.metadata = std::move(metadata);
  return clip;
}

CameraSettings shippedCamera() {  // presets/base.json's
  CameraSettings camera;
  camera.fovDeg = 50.0;
  camera.fNumber = 4.0;
  camera.sensorWidthMm = 6.2;
  return camera;
}

}  // namespace

// On a 3:2 picture the 35 mm equivalent spans 36 mm film exactly: a 50 mm equivalent is
// 2 atan(18 / 50) wide, and a 50 mm lens on it a 36 mm-wide sensor.
TEST(PlateLens, AFullFrameLensIsItsOwnEquivalent) {
  const PlateLens lens = statedLens(clipWith(
      {{"FNumber", "2.8"}, {"Exif:FocalLength", "50"}, {"Exif:FocalLengthIn35mmFilm", "50"}}, 1920,
      1280));
  EXPECT_NEAR(lens.fovDeg, 2.0 * std::atan(18.0 / 50.0) / kDeg, 1e-6);
  const CameraSettings camera = withPlateLens(shippedCamera(), lens);
  EXPECT_NEAR(camera.fovDeg, 39.5978, 1e-3);
  EXPECT_DOUBLE_EQ(camera.fNumber, 2.8);
  EXPECT_NEAR(camera.sensorWidthMm, 36.0, 1e-9);
  EXPECT_EQ(lens.stated, "FNumber 2.8, FocalLength 50 mm, FocalLengthIn35mmFilm 50 mm");
  // With overscan the picture is the display window: 1920 x 1280 inside a 2000 x 1360 frame.
  ClipInfo overscan = clipWith({{"Exif:FocalLengthIn35mmFilm", "50"}}, 2000, 1360);
  overscan.displayWindow = PixelWindow{40, 40, 1920, 1280};
  EXPECT_NEAR(statedLens(overscan).fovDeg, lens.fovDeg, 1e-9);
}

// The Lund photos' phone (an iPhone 4S: 4.3 mm at f/2.4, 35 mm equivalent, 4:3): the picture's
// width is 0.8 of the diagonal's 43.27 mm, so the view is 2 atan(17.31 / 35) and the sensor
// 4.3 mm / 35 mm of 34.61 mm wide (the phone's 1/3.2-inch sensor is 4.54 mm: within 7 %).
TEST(PlateLens, APhoneLensFromItsExif) {
  const PlateLens lens = statedLens(clipWith(
      {{"FNumber", "2.4"}, {"Exif:FocalLength", "4.3"}, {"Exif:FocalLengthIn35mmFilm", "35"}}, 1024,
      768));
  const double widthMm = std::hypot(36.0, 24.0) * 0.8;
  EXPECT_NEAR(lens.fovDeg, 2.0 * std::atan(0.5 * widthMm / 35.0) / kDeg, 1e-6);
  const CameraSettings camera = withPlateLens(shippedCamera(), lens);
  EXPECT_NEAR(camera.sensorWidthMm, widthMm * 4.3 / 35.0, 1e-6);
  EXPECT_NEAR(camera.sensorWidthMm, 4.54, 0.07 * 4.54);
}

// A focal length alone keeps the preset's view and spans the sensor it needs in it; an f-number
// alone changes the aperture only.
TEST(PlateLens, WhatIsNotStatedStaysThePresets) {
  const CameraSettings focal = withPlateLens(
      shippedCamera(), statedLens(clipWith({{"Exif:FocalLength", "24"}}, 1920, 1080)));
  EXPECT_DOUBLE_EQ(focal.fovDeg, 50.0);
  EXPECT_DOUBLE_EQ(focal.fNumber, 4.0);
  EXPECT_NEAR(focal.sensorWidthMm, 2.0 * 24.0 * std::tan(25.0 * kDeg), 1e-9);
  const CameraSettings aperture =
      withPlateLens(shippedCamera(), statedLens(clipWith({{"FNumber", "1.8"}}, 1920, 1080)));
  EXPECT_DOUBLE_EQ(aperture.fNumber, 1.8);
  EXPECT_DOUBLE_EQ(aperture.fovDeg, 50.0);
  EXPECT_DOUBLE_EQ(aperture.sensorWidthMm, 6.2);
  const PlateLens none = statedLens(clipWith({}, 1920, 1080));
  EXPECT_TRUE(none.stated.empty());
  const CameraSettings kept = withPlateLens(shippedCamera(), none);
  EXPECT_DOUBLE_EQ(kept.fovDeg, 50.0);
  EXPECT_DOUBLE_EQ(kept.sensorWidthMm, 6.2);
}

// camera.lens_from_plate false keeps every key the preset's; a field that states no lens (text,
// 0, out of range) is left out.
TEST(PlateLens, ThePresetCanRefuseThePlatesLensAndNonsenseIsLeftOut) {
  CameraSettings preset = shippedCamera();
  preset.lensFromPlate = false;
  const PlateLens lens =
      statedLens(clipWith({{"FNumber", "2.8"}, {"Exif:FocalLength", "50"}}, 1920, 1080));
  const CameraSettings kept = withPlateLens(preset, lens);
  EXPECT_DOUBLE_EQ(kept.fNumber, 4.0);
  EXPECT_DOUBLE_EQ(kept.sensorWidthMm, 6.2);
  EXPECT_NE(lensLine(kept, lens).find("camera.lens_from_plate false"), std::string::npos);
  const PlateLens nonsense = statedLens(clipWith(
      {{"FNumber", "wide"}, {"Exif:FocalLength", "0"}, {"Exif:FocalLengthIn35mmFilm", "-3"}}, 1920,
      1080));
  EXPECT_EQ(nonsense.fNumber, 0.0);
  EXPECT_EQ(nonsense.focalMm, 0.0);
  EXPECT_EQ(nonsense.fovDeg, 0.0);
  EXPECT_TRUE(nonsense.stated.empty());
}
