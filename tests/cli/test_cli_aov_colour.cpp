// An AOV's own file holds the working space's linear values and says so (issue 59: PNG AOVs read
// as sRGB while they held linear values, the AOV movies carried no transfer tag).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <OpenImageIO/imageio.h>

#include "test_support.h"
#include "util/subprocess.h"

using namespace pluvia::test;
namespace stdfs = std::filesystem;

TEST(CliAovColour, APngAovHoldsLinearValuesAndIsTaggedLinear) {
  const stdfs::path dir = freshTempDir("aov_colour_png");
  const std::string plate = writeTexturedPlate(dir, 1, 1, 96, 64);
  for (const char* output : {"o.####.png", "o.####.exr"}) {
    const auto r = runPluvia({"render", plate, "-p", "storm", "--set", "rain.seed=5", "--aov",
                              "rain", "-o", (dir / output).string()});
    ASSERT_EQ(r.exitCode, 0) << r.output;
  }
  // Read as stored: the layer is premultiplied, its A the coverage (OpenImageIO would multiply
  // the RGB by A again, as for a PNG's straight alpha).
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto input = OIIO::ImageInput::open((dir / "o.rain.0001.png").string(), &config);
  ASSERT_TRUE(input);
  EXPECT_EQ(input->spec().get_string_attribute("oiio:ColorSpace"), "linear");
  pluvia::Image png(input->spec().width, input->spec().height);
  ASSERT_EQ(input->spec().nchannels, 4);
  ASSERT_TRUE(input->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, png.rgba.data()));
  input->close();
  // The PNG's codes are the EXR's linear rain.R over 255, to 8-bit rounding (and half's).
  const ExrPixels exr = readAllChannels(dir / "o.0001.exr");
  const auto at = std::find(exr.channels.begin(), exr.channels.end(), "rain.R");
  ASSERT_NE(at, exr.channels.end());
  const size_t channel = size_t(at - exr.channels.begin()), count = exr.channels.size();
  ASSERT_EQ(exr.samples.size(), png.pixelCount() * count);
  double largest = 0.0, sum = 0.0;
  for (size_t i = 0; i < png.pixelCount(); ++i) {
    const float linear = exr.samples[i * count + channel];
    largest = std::max(largest, double(std::fabs(png.rgba[i * 4] - std::min(linear, 1.0f))));
    sum += linear;
  }
  EXPECT_GT(sum, 1.0) << "the storm's rain layer holds light";
  EXPECT_LE(largest, 0.5 / 255 + 1e-3);
}

TEST(CliAovColour, AnAovMovieIsTaggedLinear) {
  if (!pluvia::programAvailable("ffprobe")) GTEST_SKIP() << "ffprobe not on PATH";
  const stdfs::path dir = freshTempDir("aov_colour_movie");
  const std::string plate = writeTexturedPlate(dir, 1, 2, 96, 64);
  const auto r = runPluvia({"render", plate, "-p", "moderate", "--aov", "rain", "--codec",
                            "prores_4444", "-o", (dir / "o.mov").string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const pluvia::ProcessResult probe =
      pluvia::runProcess({"ffprobe", "-v", "error", "-show_entries", "stream=color_transfer", "-of",
                          "flat", (dir / "o.rain.mov").string()});
  EXPECT_NE(probe.output.find("color_transfer=\"linear\""), std::string::npos) << probe.output;
}
