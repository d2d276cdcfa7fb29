// depth.source = "file": depth files written with known values (float EXR Z, 16-bit PNG) read
// back in each encoding, the channel chosen, resampling to another size, and the missing-frame
// error. Tolerances: float EXR values come back bit-exact (z_m, scale 1) or within float
// rounding of the decoding (1e-6 relative); 16-bit codes within float rounding of code / 65535
// (1e-6 relative), and a depth quantised to 16 bits within half a code step of the true depth.
#include "io/depth_sequence.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "oiio_files.h"
#include "test_support.h"
#include "util/error.h"

namespace pluvia {
namespace {
namespace stdfs = std::filesystem;

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Writes `samples` (interleaved, `names.size()` channels, given as `dataType`) to a file whose
// samples are `fileType`; `dataX`/`dataY` offset the data window inside a display window of
// displayWidth x displayHeight (0: the data window is the frame).
template <typename Sample>
void writeFile(const stdfs::path& path, int width, int height,
               const std::vector<std::string>& names, OIIO::TypeDesc fileType,
               OIIO::TypeDesc dataType, const std::vector<Sample>& samples, int dataX = 0,
               int dataY = 0, int displayWidth = 0, int displayHeight = 0) {
  OIIO::ImageSpec spec = test::windowedSpec(width, height, static_cast<int>(names.size()), fileType,
                                            dataX, dataY, displayWidth > 0 ? displayWidth : width,
                                            displayHeight > 0 ? displayHeight : height);
  spec.channelnames = names;
  test::writeWithSpec(path, spec, samples.data(), dataType);
}

void writeExrZ(const stdfs::path& path, int width, int height, const std::vector<float>& z) {
  writeFile(path, width, height, {"Z"}, OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::FLOAT, z);
}

void writePng16(const stdfs::path& path, int width, int height,
                const std::vector<uint16_t>& codes) {
  writeFile(path, width, height, {"Y"}, OIIO::TypeDesc::UINT16, OIIO::TypeDesc::UINT16, codes);
}

DepthDecoding decodingOf(DepthEncoding encoding, double scale = 1.0, double nearMeters = 1.0,
                         double farMeters = 100.0) {
  return DepthDecoding{encoding, scale, nearMeters, farMeters};
}

void expectNearRelative(float actual, double expected, const std::string& what) {
  EXPECT_NEAR(actual, expected, 1e-6 * expected) << what;
}

TEST(DepthSequence, EncodingNames) {
  EXPECT_EQ(depthEncodingFromName("z_m"), DepthEncoding::ZMeters);
  EXPECT_EQ(depthEncodingFromName("inverse"), DepthEncoding::Inverse);
  EXPECT_EQ(depthEncodingFromName("normalized"), DepthEncoding::Normalized);
  EXPECT_THROW(depthEncodingFromName("metres"), Error);
}

TEST(DepthSequence, ExrZInMetresComesBackExactlyAndNonPositiveIsSky) {
  const auto dir = test::freshTempDir("depth_exr_z_m");
  const std::vector<float> stored{0.5f, 6.0f, 12345.678f, 0.0f, -2.0f, kNaN, kInf, 1e-3f};
  writeExrZ(dir / "z.exr", 4, 2, stored);

  const DepthPlane plane =
      readDepthFile((dir / "z.exr").string(), decodingOf(DepthEncoding::ZMeters), 0);
  ASSERT_EQ(plane.width, 4);
  ASSERT_EQ(plane.height, 2);
  const std::vector<float> expected{0.5f, 6.0f, 12345.678f, kInf, kInf, kInf, kInf, 1e-3f};
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(plane.meters[i], expected[i]) << i;

  // file_scale: metres per file unit (a file in centimetres: 0.01).
  const DepthPlane centimetres =
      readDepthFile((dir / "z.exr").string(), decodingOf(DepthEncoding::ZMeters, 0.01), 0);
  expectNearRelative(centimetres.meters[1], 0.06, "6 cm");
  expectNearRelative(centimetres.meters[2], 123.45678, "12345.678 cm");
  EXPECT_EQ(centimetres.meters[3], kInf);
}

TEST(DepthSequence, ExrInverseAndNormalized) {
  const auto dir = test::freshTempDir("depth_exr_encodings");
  const std::vector<float> stored{0.25f, 0.5f, 0.0f, 1.0f};
  writeExrZ(dir / "v.exr", 2, 2, stored);
  const std::string path = (dir / "v.exr").string();

  // inverse: z = scale / v, v == 0 is sky.
  const DepthPlane inverse = readDepthFile(path, decodingOf(DepthEncoding::Inverse, 10.0), 0);
  expectNearRelative(inverse.meters[0], 40.0, "10 / 0.25");
  expectNearRelative(inverse.meters[1], 20.0, "10 / 0.5");
  EXPECT_EQ(inverse.meters[2], kInf);
  expectNearRelative(inverse.meters[3], 10.0, "10 / 1");

  // normalized: z = near + v * (far - near).
  const DepthPlane normalized =
      readDepthFile(path, decodingOf(DepthEncoding::Normalized, 1.0, 2.0, 102.0), 0);
  expectNearRelative(normalized.meters[0], 27.0, "v = 0.25");
  expectNearRelative(normalized.meters[1], 52.0, "v = 0.5");
  expectNearRelative(normalized.meters[2], 2.0, "v = 0: near");
  expectNearRelative(normalized.meters[3], 102.0, "v = 1: far");
}

TEST(DepthSequence, Png16CodesAreNormalisedBeforeTheEncoding) {
  const auto dir = test::freshTempDir("depth_png16");
  const std::vector<uint16_t> codes{0, 1, 32768, 65535};
  writePng16(dir / "d.png", 2, 2, codes);
  const std::string path = (dir / "d.png").string();

  const DepthPlane normalized =
      readDepthFile(path, decodingOf(DepthEncoding::Normalized, 1.0, 1.0, 101.0), 0);
  const DepthPlane inverse = readDepthFile(path, decodingOf(DepthEncoding::Inverse, 2.0), 0);
  const DepthPlane meters = readDepthFile(path, decodingOf(DepthEncoding::ZMeters, 65.535), 0);
  for (size_t i = 0; i < codes.size(); ++i) {
    const double v = codes[i] / 65535.0;
    const std::string what = fmt::format("code {}", codes[i]);
    expectNearRelative(normalized.meters[i], 1.0 + v * 100.0, what);
    if (codes[i] == 0) {
      EXPECT_EQ(inverse.meters[i], kInf) << what;
      EXPECT_EQ(meters.meters[i], kInf) << what;
    } else {
      expectNearRelative(inverse.meters[i], 2.0 / v, what);
      expectNearRelative(meters.meters[i], 65.535 * v, what);  // millimetres stored
    }
  }
}

TEST(DepthSequence, DepthQuantisedTo16BitsComesBackWithinHalfACodeStep) {
  const auto dir = test::freshTempDir("depth_png16_quantised");
  const double nearMeters = 0.5, farMeters = 80.0;
  const int width = 64, height = 4;
  std::vector<double> trueMeters;
  std::vector<uint16_t> codes;
  for (int i = 0; i < width * height; ++i) {
    const double z = nearMeters + (farMeters - nearMeters) * std::pow(i / 255.0, 2.0);
    trueMeters.push_back(z);
    codes.push_back(
        static_cast<uint16_t>(std::lround((z - nearMeters) / (farMeters - nearMeters) * 65535.0)));
  }
  writePng16(dir / "d.png", width, height, codes);
  const DepthPlane plane =
      readDepthFile((dir / "d.png").string(),
                    decodingOf(DepthEncoding::Normalized, 1.0, nearMeters, farMeters), 0);
  const double halfStepMeters = 0.5 * (farMeters - nearMeters) / 65535.0;
  for (size_t i = 0; i < trueMeters.size(); ++i)
    EXPECT_NEAR(plane.meters[i], trueMeters[i], halfStepMeters + 1e-6 * trueMeters[i]) << i;
}

TEST(DepthSequence, ChannelPreferenceZThenDepthZThenYThenR) {
  const auto dir = test::freshTempDir("depth_channels");
  const auto decoding = decodingOf(DepthEncoding::ZMeters);
  const std::vector<float> rgbz{1, 2, 3, 4};
  writeFile(dir / "rgbz.exr", 1, 1, {"R", "G", "B", "Z"}, OIIO::TypeDesc::FLOAT,
            OIIO::TypeDesc::FLOAT, rgbz);
  EXPECT_EQ(readDepthFile((dir / "rgbz.exr").string(), decoding, 0).meters[0], 4.0f);
  const std::vector<float> layered{1, 2, 3, 5};
  writeFile(dir / "layered.exr", 1, 1, {"R", "G", "B", "depth.Z"}, OIIO::TypeDesc::FLOAT,
            OIIO::TypeDesc::FLOAT, layered);
  EXPECT_EQ(readDepthFile((dir / "layered.exr").string(), decoding, 0).meters[0], 5.0f);
  const std::vector<float> rgb{7, 8, 9};
  writeFile(dir / "rgb.exr", 1, 1, {"R", "G", "B"}, OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::FLOAT,
            rgb);
  EXPECT_EQ(readDepthFile((dir / "rgb.exr").string(), decoding, 0).meters[0], 7.0f);
  const std::vector<float> single{11};
  writeFile(dir / "depth.exr", 1, 1, {"distance"}, OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::FLOAT,
            single);
  EXPECT_EQ(readDepthFile((dir / "depth.exr").string(), decoding, 0).meters[0], 11.0f);
  // Two channels, neither of them a known one: refused, naming the file and the channels.
  const std::vector<float> uv{1, 2};
  const std::string uvPath = (dir / "uv.exr").string();
  writeFile(uvPath, 1, 1, {"U", "V"}, OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::FLOAT, uv);
  try {
    readDepthFile(uvPath, decoding, 3);
    ADD_FAILURE() << "no error for channels U, V";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(uvPath), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("U, V"), std::string::npos) << e.what();
    EXPECT_EQ(e.context().frame.value_or(-1), 3);
  }
}

TEST(DepthSequence, OutsideTheDataWindowIsSky) {
  const auto dir = test::freshTempDir("depth_data_window");
  // A 2x1 data window at (1, 1) in a 4x3 frame.
  const std::vector<float> z{3, 4};
  writeFile(dir / "z.exr", 2, 1, {"Z"}, OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::FLOAT, z, 1, 1, 4,
            3);
  const DepthPlane plane =
      readDepthFile((dir / "z.exr").string(), decodingOf(DepthEncoding::ZMeters), 0);
  ASSERT_EQ(plane.width, 4);
  ASSERT_EQ(plane.height, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x) {
      const float expected = y == 1 && x == 1 ? 3.0f : y == 1 && x == 2 ? 4.0f : kInf;
      EXPECT_EQ(plane.meters[y * 4 + x], expected) << x << "," << y;
    }
}

TEST(DepthSequence, ResamplingIsBilinearOnInverseDepth) {
  // 2x1 -> 4x1: output centres fall at source x = -0.25 (clamped to 0), 0.25, 0.75, 1.25
  // (clamped to 1). Between 5 m (1/z = 0.2) and sky (0): 1 / 0.15 and 1 / 0.05.
  const DepthPlane edge{2, 1, {5.0f, kInf}};
  const std::vector<float> wide = resampleDepth(edge, 4, 1);
  ASSERT_EQ(wide.size(), 4u);
  expectNearRelative(wide[0], 5.0, "left");
  expectNearRelative(wide[1], 1.0 / 0.15, "a quarter of the way to the sky");
  expectNearRelative(wide[2], 1.0 / 0.05, "three quarters of the way to the sky");
  EXPECT_EQ(wide[3], kInf);
  // A uniform area stays its depth; the same size comes back bit-exact.
  const DepthPlane flat{3, 2, std::vector<float>(6, 6.0f)};
  for (float z : resampleDepth(flat, 7, 5)) expectNearRelative(z, 6.0, "uniform 6 m");
  const DepthPlane odd{2, 1, {1.2345678f, 98.7654321f}};
  EXPECT_EQ(resampleDepth(odd, 2, 1), odd.meters);
}

TEST(DepthSequence, ReadsTheFrameByNumberResampledToThePlate) {
  const auto dir = test::freshTempDir("depth_sequence_read");
  for (int frame : {1001, 1002})
    writeExrZ(dir / fmt::format("z.{:04d}.exr", frame), 2, 1,
              {static_cast<float>(frame - 1000), kInf});
  const DepthSequence sequence((dir / "z.####.exr").string(), decodingOf(DepthEncoding::ZMeters));
  EXPECT_FALSE(sequence.singleFile());
  EXPECT_EQ(sequence.pathFor(1002), (dir / "z.1002.exr").string());
  const std::vector<float> frame2 = sequence.read(1002, 4, 2);  // plate 4x2: resampled
  ASSERT_EQ(frame2.size(), 8u);
  for (int y = 0; y < 2; ++y) {
    expectNearRelative(frame2[y * 4 + 0], 2.0, "frame 1002, left");
    expectNearRelative(frame2[y * 4 + 1], 1.0 / (0.75 * 0.5), "frame 1002, towards the sky");
    EXPECT_EQ(frame2[y * 4 + 3], kInf);
  }
  // A printf pattern names the same files.
  const DepthSequence printf((dir / "z.%04d.exr").string(), decodingOf(DepthEncoding::ZMeters));
  EXPECT_EQ(printf.read(1001, 2, 1)[0], 1.0f);
}

TEST(DepthSequence, OneFileServesEveryFrame) {
  const auto dir = test::freshTempDir("depth_single_file");
  writeExrZ(dir / "z.exr", 1, 1, {8.0f});
  const DepthSequence single((dir / "z.exr").string(), decodingOf(DepthEncoding::ZMeters));
  EXPECT_TRUE(single.singleFile());
  EXPECT_NO_THROW(single.requireFrames({0, 1, 500}));
  EXPECT_EQ(single.read(500, 1, 1)[0], 8.0f);
}

TEST(DepthSequence, MissingFrameErrorNamesTheFile) {
  const auto dir = test::freshTempDir("depth_missing");
  for (int frame : {1, 2, 4}) writeExrZ(dir / fmt::format("z.{:04d}.exr", frame), 1, 1, {1.0f});
  const DepthSequence sequence((dir / "z.####.exr").string(), decodingOf(DepthEncoding::ZMeters));
  EXPECT_NO_THROW(sequence.requireFrames({1, 2, 4}));
  const std::string missing = (dir / "z.0003.exr").string();
  try {
    sequence.requireFrames({1, 2, 3, 4});
    ADD_FAILURE() << "no error for frame 3";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    EXPECT_EQ(e.context().file, missing);
    EXPECT_EQ(e.context().frame.value_or(-1), 3);
  }
  // Neither an existing file nor a pattern; a folder.
  EXPECT_THROW(DepthSequence((dir / "nothing.exr").string(), {}), Error);
  EXPECT_THROW(DepthSequence(dir.string(), {}), Error);
}

}  // namespace
}  // namespace pluvia
