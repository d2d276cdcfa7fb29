// camera.exposure_s 0 (auto) takes the shutter the plate's files state (ExposureTime, as photo
// and phone cameras write it), before guessing one from the picture: a grey EXR stating 1/250 s
// is filmed at 1/250 s, the same plate without the attribute at the daylight guess.
#include <gtest/gtest.h>

#include <vector>

#include "oiio_files.h"
#include "test_support.h"

using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

constexpr int kWidth = 96, kHeight = 64;

std::string greyPlate(const stdfs::path& dir, const std::string& name, float exposureSeconds) {
  OIIO::ImageSpec spec(kWidth, kHeight, 3, OIIO::TypeDesc::HALF);
  if (exposureSeconds > 0.0f) spec.attribute("ExposureTime", exposureSeconds);
  const std::vector<float> grey(size_t(kWidth) * kHeight * 3, 0.18f);
  writeWithSpec(dir / (name + ".0001.exr"), spec, grey.data());
  return (dir / (name + ".####.exr")).string();
}

}  // namespace

TEST(CliPlateShutter, AutoExposureTakesTheShutterThePlateStates) {
  const stdfs::path dir = freshTempDir("plate_shutter");
  const auto stated = runPluvia({"render", greyPlate(dir, "stated", 0.004f), "-p", "moderate", "-o",
                                 (dir / "a.####.exr").string()});
  ASSERT_EQ(stated.exitCode, 0) << stated.output;
  EXPECT_NE(stated.output.find("rain: camera.exposure_s 0 (auto): 1/250 s (the plate's metadata: "
                               "ExposureTime 0.004 s)"),
            std::string::npos)
      << stated.output;

  const auto unstated = runPluvia({"render", greyPlate(dir, "plain", 0.0f), "-p", "moderate", "-o",
                                   (dir / "b.####.exr").string()});
  ASSERT_EQ(unstated.exitCode, 0) << unstated.output;
  EXPECT_NE(unstated.output.find("rain: camera.exposure_s 0 (auto): 1/600 s (a day plate)"),
            std::string::npos)
      << unstated.output;
}
