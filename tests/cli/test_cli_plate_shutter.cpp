// camera.exposure_s 0 (every shipped preset) films the rain with the plate camera's shutter: what
// the plate's files state (ExposureTime, a shutter angle), else what its motion blur shows, else
// the 180-degree shutter of its frame rate. The render's log and `pluvia plan` say which and the
// value. The lens the plate's files state films it too.
#include <gtest/gtest.h>

#include <vector>

#include "oiio_files.h"
#include "test_support.h"

using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

constexpr int kWidth = 96, kHeight = 64;

// A grey one-frame EXR sequence with `attributes` set on its header.
std::string greyPlate(const stdfs::path& dir, const std::string& name,
                      const std::function<void(OIIO::ImageSpec&)>& attributes) {
  OIIO::ImageSpec spec(kWidth, kHeight, 3, OIIO::TypeDesc::HALF);
  attributes(spec);
  const std::vector<float> grey(size_t(kWidth) * kHeight * 3, 0.18f);
  writeWithSpec(dir / (name + ".0001.exr"), spec, grey.data());
  return (dir / (name + ".####.exr")).string();
}

std::string renderLog(const stdfs::path& dir, const std::string& plate, const std::string& name) {
  const auto rendered =
      runPluvia({"render", plate, "-p", "moderate", "-o", (dir / (name + ".####.exr")).string()});
  EXPECT_EQ(rendered.exitCode, 0) << rendered.output;
  return rendered.output;
}

}  // namespace

TEST(CliPlateShutter, TheShutterThePlateStatesFilmsTheRain) {
  const stdfs::path dir = freshTempDir("plate_shutter");
  const std::string exposure =
      greyPlate(dir, "exposure", [](OIIO::ImageSpec& s) { s.attribute("ExposureTime", 0.004f); });
  EXPECT_NE(renderLog(dir, exposure, "a")
                .find("rain: shutter 1/250 s, the plate's metadata (ExposureTime 0.004 s)"),
            std::string::npos);
  // An angle (ARRI's name) at the sequence's 24 fps: 172.8 / 360 / 24 = 1/50 s.
  const std::string angle = greyPlate(dir, "angle", [](OIIO::ImageSpec& s) {
    s.attribute("com.arri.camera.ShutterAngle", 172.8f);
  });
  EXPECT_NE(renderLog(dir, angle, "b")
                .find("rain: shutter 1/50 s, the plate's metadata (shutter "
                      "angle 172.8 deg at 24 fps)"),
            std::string::npos);
}

// A field that states no shutter (a negative angle, text for a time) is said and left out.
TEST(CliPlateShutter, MetadataThatStatesNoShutterIsSaidAndLeftOut) {
  const stdfs::path dir = freshTempDir("plate_shutter_unusable");
  const std::string angle = greyPlate(
      dir, "angle", [](OIIO::ImageSpec& s) { s.attribute("com.arri.camera.ShutterAngle", -5.0f); });
  const std::string log = renderLog(dir, angle, "d");
  EXPECT_NE(log.find("plate: ShutterAngle '-5' in the metadata of"), std::string::npos) << log;
  EXPECT_NE(log.find("rain: shutter 1/48 s, the 180-degree shutter"), std::string::npos) << log;
}

TEST(CliPlateShutter, AStillWithoutMetadataIsFilmedAtTheHalfOpenShutter) {
  const stdfs::path dir = freshTempDir("plate_shutter_still");
  const std::string plain = greyPlate(dir, "plain", [](OIIO::ImageSpec&) {});
  EXPECT_NE(renderLog(dir, plain, "c")
                .find("rain: shutter 1/48 s, the 180-degree shutter at the plate's 24 fps (no "
                      "shutter in its metadata, and a still shows no motion blur to measure)"),
            std::string::npos);
}

TEST(CliPlateShutter, PlanNamesTheShutterAndItsSource) {
  const stdfs::path dir = freshTempDir("plate_shutter_plan");
  const std::string exposure =
      greyPlate(dir, "exposure", [](OIIO::ImageSpec& s) { s.attribute("ExposureTime", 0.004f); });
  const auto stated = runPluvia({"plan", exposure, "-p", "moderate"});
  ASSERT_EQ(stated.exitCode, 0) << stated.output;
  EXPECT_NE(stated.output.find("shutter 1/250 s: the plate's metadata (ExposureTime 0.004 s); "
                               "camera.exposure_s or camera.shutter_angle_deg sets another"),
            std::string::npos)
      << stated.output;

  // The bundled example's preset leaves the shutter to its plate: a movie with no shutter tag,
  // timed by its motion blur. Its walkers move 2-7 px a frame at 10 fps, and a short shutter
  // smears them by a third of a pixel against a still edge's 0.75 px blur: read from its own
  // 8-bit codes it is at most 1/178 s (the blur too short to see), through swscale's rounded RGB
  // it read as 1/138 s. Either way the source is the motion blur.
  const std::string example = (sourceDir() / "examples/street/street_plate.mp4").string();
  const auto bundled =
      runPluvia({"plan", example, "-p", (sourceDir() / "examples/street/street.json").string()});
  ASSERT_EQ(bundled.exitCode, 0) << bundled.output;
  EXPECT_NE(bundled.output.find("measured from the plate's motion blur"), std::string::npos)
      << bundled.output;
  // A preset's angle over the plate's own shutter.
  const auto angle =
      runPluvia({"plan", exposure, "-p", "moderate", "--set", "camera.shutter_angle_deg=180"});
  EXPECT_NE(
      angle.output.find("shutter 1/48 s: the preset's camera.shutter_angle_deg 180 at 24 fps"),
      std::string::npos)
      << angle.output;
}

// NTURain's slow pan (2-3 px a frame at 640 px) blurs no edge visibly: its motion blur bounds the
// shutter (at most 1/159 s). It was shot in rain, and its own streaks say more: by their light
// 7.6 times as long as wide, 1/553 s (pluvia match found its rain at 1/622 s; the median streak,
// 6.2 x 1.16 px, a far drop as wide as the blur, read 1/846 s). A proxy measures the frames at
// their filmed size and finds the same (at half of it the pan moves too little, and the streaks'
// widths are a pixel's).
TEST(CliPlateShutter, RealRainFootageIsFilmedAtTheShutterItsStreaksShow) {
  const stdfs::path clip = sharedData() / "rain_real/nturain_ra1_real_rain_panning/#####.jpg";
  if (!stdfs::exists(sharedData() / "rain_real/nturain_ra1_real_rain_panning/00001.jpg"))
    GTEST_SKIP() << "../shared/data is absent";
  const auto plan = runPluvia({"plan", clip.string(), "-p", "moderate"});
  ASSERT_EQ(plan.exitCode, 0) << plan.output;
  const std::string streaks =
      "the streaks of the plate's own rain (by their light 7.6 times as long as wide, the median "
      "6.2 x 1.16 px";
  EXPECT_NE(plan.output.find("shutter 1/553 s: " + streaks), std::string::npos) << plan.output;
  EXPECT_NE(plan.output.find("shorter than 1/159 s (at most, measured from the plate's motion "
                             "blur at 24 fps"),
            std::string::npos)
      << plan.output;
  const stdfs::path dir = freshTempDir("plate_shutter_proxy");
  const auto proxy = runPluvia({"render", clip.string(), "-p", "moderate", "--frames", "3-3",
                                "--proxy", "0.5", "-o", (dir / "p.####.png").string()});
  ASSERT_EQ(proxy.exitCode, 0) << proxy.output;
  EXPECT_NE(proxy.output.find("rain: shutter 1/553 s, " + streaks), std::string::npos)
      << proxy.output;
}

// The lens the plate states films the rain too (pipeline/plate_lens.h): a full-frame 50 mm at
// f/1.4 (EXR aperture and EXIF focal lengths) defocuses near drops so much that the nearest
// drawn are 0.95 m away (blurred over 5 % of the 96 px width: 20 m / (1 + 4.8 px / k), k = A f /
// (s - f) px/mm = 0.2387 px), where the shipped phone-like lens draws from 0.30 m; the plan names
// it; camera.lens_from_plate false keeps the preset's.
TEST(CliPlateShutter, TheLensThePlateStatesFilmsTheRain) {
  const stdfs::path dir = freshTempDir("plate_lens");
  const std::string plate = greyPlate(dir, "lens", [](OIIO::ImageSpec& s) {
    s.attribute("FNumber", 1.4f);
    s.attribute("Exif:FocalLength", 50.0f);
    s.attribute("Exif:FocalLengthIn35mmFilm", 50);
  });
  const std::string log = renderLog(dir, plate, "a");
  EXPECT_NE(
      log.find("rain: lens 39.6 deg view, f/1.4, 50.00 mm focal length on a 36.00 mm-wide "
               "sensor, focused at 20 m: the plate's metadata (FNumber 1.4, FocalLength 50 mm, "
               "FocalLengthIn35mmFilm 50 mm)"),
      std::string::npos)
      << log;
  EXPECT_NE(log.find("rain: drops from 0.95 to"), std::string::npos) << log;
  const auto plan = runPluvia({"plan", plate, "-p", "moderate"});
  ASSERT_EQ(plan.exitCode, 0) << plan.output;
  EXPECT_NE(plan.output.find("lens 39.6 deg view, f/1.4"), std::string::npos) << plan.output;

  const auto preset =
      runPluvia({"render", plate, "-p", "moderate", "--set", "camera.lens_from_plate=false", "-o",
                 (dir / "b.####.exr").string()});
  ASSERT_EQ(preset.exitCode, 0) << preset.output;
  EXPECT_NE(preset.output.find(
                "rain: lens 50.0 deg view, f/4, 6.65 mm focal length on a 6.20 "
                "mm-wide sensor, focused at 20 m: the preset's (camera.lens_from_plate false"),
            std::string::npos)
      << preset.output;
  EXPECT_NE(preset.output.find("rain: drops from 0.30 to"), std::string::npos) << preset.output;
}
