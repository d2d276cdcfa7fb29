// Image files that were read silently wrong or refused in a library's words (issue 59's
// adversarial pass): a deep EXR, a two-part EXR, a JPEG cut short, an EXIF orientation.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <vector>

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imageio.h>

#include "io/image_file_reader.h"
#include "oiio_files.h"
#include "test_support.h"
#include "util/error.h"

namespace pluvia {
namespace {
namespace stdfs = std::filesystem;

// 4 x 3 pixels, each a different grey: pixel (x, y) is (10 y + x) / 100.
std::vector<float> numberedPixels() {
  std::vector<float> samples;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x)
      for (int c = 0; c < 3; ++c) samples.push_back(float(10 * y + x) / 100.0f);
  return samples;
}

TEST(ImageFileOddities, ADeepExrIsRefusedNamingWhatItIs) {
  const stdfs::path dir = test::freshTempDir("odd_deep");
  OIIO::ImageSpec spec(4, 3, 4, OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"R", "G", "B", "Z"};
  spec.deep = true;
  spec.z_channel = 3;
  auto out = OIIO::ImageOutput::create("exr");
  const stdfs::path path = dir / "deep.exr";
  ASSERT_TRUE(out->open(path.string(), spec)) << out->geterror();
  OIIO::DeepData deep(spec);
  for (int64_t p = 0; p < 12; ++p) deep.set_samples(p, 1);
  ASSERT_TRUE(out->write_deep_image(deep)) << out->geterror();
  out->close();
  test::expectError([&] { readImageFile(path.string(), std::nullopt); },
                    "is a deep image (several samples a pixel)");
}

TEST(ImageFileOddities, ATwoPartExrReadsItsFirstPart) {
  const stdfs::path dir = test::freshTempDir("odd_parts");
  const stdfs::path path = dir / "two.exr";
  std::vector<OIIO::ImageSpec> specs(2, OIIO::ImageSpec(4, 3, 3, OIIO::TypeDesc::FLOAT));
  specs[0].attribute("name", "beauty");
  specs[1].attribute("name", "other");
  auto out = OIIO::ImageOutput::create("exr");
  ASSERT_TRUE(out->open(path.string(), 2, specs.data())) << out->geterror();
  const std::vector<float> first = numberedPixels(), second(36, 0.9f);
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, first.data()));
  ASSERT_TRUE(out->open(path.string(), specs[1], OIIO::ImageOutput::AppendSubimage));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, second.data()));
  out->close();
  testing::internal::CaptureStderr();
  const Image image = readImageFile(path.string(), std::nullopt);
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("holds 2 parts ('beauty', 'other'): pluvia reads the first, 'beauty'"),
            std::string::npos)
      << said;
  EXPECT_FLOAT_EQ(image.rgba[(2 * 4 + 3) * 4], 0.23f);
}

TEST(ImageFileOddities, AJpegCutShortIsRefused) {
  const stdfs::path dir = test::freshTempDir("odd_jpeg");
  Image picture(64, 48);
  for (size_t i = 0; i < picture.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c) picture.rgba[i * 4 + c] = float((i * (c + 3)) % 97) / 97.0f;
  test::writeImageFile(dir / "whole.jpg", picture);
  std::ifstream in(dir / "whole.jpg", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(dir / "cut.jpg", std::ios::binary) << bytes.substr(0, bytes.size() * 2 / 3);
  EXPECT_EQ(readImageFile((dir / "whole.jpg").string(), std::nullopt).width, 64);
  // It decoded with a grey lower third and no error.
  test::expectError([&] { readImageFile((dir / "cut.jpg").string(), std::nullopt); },
                    "Premature end of JPEG file");
}

TEST(ImageFileOddities, AnExifOrientationIsReadUpright) {
  const stdfs::path dir = test::freshTempDir("odd_orientation");
  OIIO::ImageSpec spec(4, 3, 3, OIIO::TypeDesc::UINT16);
  spec.attribute("Orientation", 6);  // shown turned a quarter clockwise
  const std::vector<float> samples = numberedPixels();
  test::writeWithSpec(dir / "turned.tif", spec, samples.data());
  const ImageFileHeader header = readImageHeader((dir / "turned.tif").string(), std::nullopt);
  EXPECT_EQ(header.width, 3);
  EXPECT_EQ(header.height, 4);
  const Image image = readImageFile((dir / "turned.tif").string(), std::nullopt);
  ASSERT_EQ(image.width, 3);
  ASSERT_EQ(image.height, 4);
  // Turned clockwise: the stored top row is the right column, read top to bottom.
  for (int x = 0; x < 4; ++x)
    EXPECT_NEAR(image.rgba[(size_t(x) * 3 + 2) * 4], float(x) / 100.0f, 1e-4) << x;
  // The stored left column is the top row, read right to left.
  for (int y = 0; y < 3; ++y)
    EXPECT_NEAR(image.rgba[size_t(2 - y) * 4], float(10 * y) / 100.0f, 1e-4) << y;
}

}  // namespace
}  // namespace pluvia
