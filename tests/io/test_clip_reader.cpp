#include "io/clip_reader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include "oiio_files.h"
#include "test_support.h"
#include "util/error.h"
#include "util/subprocess.h"

namespace pluvia {
namespace {

using test::expectError;
namespace stdfs = std::filesystem;

// Writes interleaved float samples to a file of the given sample type, keeping alpha straight.
void writeSamples(const stdfs::path& path, int width, int height, int channels, OIIO::TypeDesc type,
                  const std::vector<float>& samples) {
  OIIO::ImageSpec spec(width, height, channels, type);
  if (channels == 2) spec.channelnames = {"Y", "A"};
  if (channels == 1) spec.channelnames = {"Y"};
  spec.alpha_channel = channels == 2 ? 1 : channels == 4 ? 3 : -1;
  spec.attribute("oiio:UnassociatedAlpha", 1);
  test::writeWithSpec(path, spec, samples.data());
}

// A ramp where every sample is a distinct multiple of 1/levels.
std::vector<float> ramp(int width, int height, int channels, int levels) {
  std::vector<float> samples(static_cast<size_t>(width) * height * channels);
  for (size_t i = 0; i < samples.size(); ++i)
    samples[i] = static_cast<float>((i * 37) % (levels + 1)) / levels;
  return samples;
}

void cutFile(const stdfs::path& from, const stdfs::path& to, double fraction) {
  std::ifstream in(from, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(to, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size() * fraction));
}

TEST(ClipReaderMovie, ExampleClipInfo) {
  auto clip = openClip(test::exampleClip().string());
  const ClipInfo& info = clip->info();
  EXPECT_TRUE(info.isMovie);
  EXPECT_FALSE(info.isFloat);
  EXPECT_EQ(info.width, 768);
  EXPECT_EQ(info.height, 576);
  EXPECT_DOUBLE_EQ(info.fps, 10.0);
  ASSERT_EQ(info.frames.size(), 48u);
  EXPECT_EQ(info.frames.front(), 0);
  EXPECT_EQ(info.frames.back(), 47);
  EXPECT_EQ(info.files, std::vector<std::string>{test::exampleClip().string()});
}

// The example is 8-bit H.264 Y'CbCr: R'G'B' from its codes, beyond [0, 1] where they are (its
// shadows hold sub-blacks, Y' under 16, which swscale's RGB clipped to 0).
TEST(ClipReaderMovie, PixelsAreRgbFromTheCodesWithOpaqueAlpha) {
  auto clip = openClip(test::exampleClip().string());
  Image frame = clip->read(0);
  ASSERT_EQ(frame.width, 768);
  ASSERT_EQ(frame.height, 576);
  float low = 1.0f, high = 0.0f;
  size_t below = 0;
  for (size_t i = 0; i < frame.pixelCount(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const float v = frame.rgba[i * 4 + c];
      low = std::min(low, v);
      high = std::max(high, v);
      below += v < -0.5f / 255.0f;
    }
    ASSERT_EQ(frame.rgba[i * 4 + 3], 1.0f);
  }
  EXPECT_GT(low, -0.5f);
  EXPECT_LT(high, 1.5f);
  EXPECT_GT(high - low, 0.3f) << "a street plate has contrast";
  EXPECT_GT(double(below) / double(3 * frame.pixelCount()), 0.005) << "the sub-blacks are kept";
}

TEST(ClipReaderMovie, FramesMatchFfmpegsOwnDecoding) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  auto dir = test::freshTempDir("reader_movie_vs_ffmpeg");
  auto clip = openClip(test::exampleClip().string());
  for (int64_t frame : {0, 10, 47}) {
    const stdfs::path png = dir / ("frame" + std::to_string(frame) + ".png");
    ASSERT_EQ(
        runProcess({"ffmpeg", "-v", "error", "-i", test::exampleClip().string(), "-vf",
                    "select=eq(n\\," + std::to_string(frame) + ")", "-frames:v", "1", "-sws_flags",
                    "accurate_rnd+full_chroma_int", "-pix_fmt", "rgb24", png.string()})
            .exitCode,
        0);
    Image expected = test::readImageFile(png);
    Image actual = clip->read(frame);
    ASSERT_EQ(actual.width, expected.width);
    ASSERT_EQ(actual.height, expected.height);
    // ffmpeg's exact conversion to 8-bit RGB (BT.601 for this untagged SD movie), clipped and
    // rounded: within half a code on average of the reader's values clipped to [0, 1] (0.37
    // measured: the rounding, and swscale's own chroma upsampling). A red/blue swap, a wrong
    // frame or the BT.709 matrix (1.9 codes off) would fail.
    double difference = 0;
    for (size_t i = 0; i < actual.pixelCount(); ++i)
      for (size_t c = 0; c < 3; ++c)
        difference +=
            std::abs(std::clamp(actual.rgba[i * 4 + c], 0.0f, 1.0f) - expected.rgba[i * 4 + c]);
    EXPECT_LT(difference / double(3 * actual.pixelCount()), 0.5 / 255) << "frame " << frame;
  }
}

TEST(ClipReaderMovie, SeekingBackMatchesSequentialDecoding) {
  std::vector<Image> sequential;
  {
    auto clip = openClip(test::exampleClip().string());
    for (int64_t frame = 0; frame <= 8; ++frame) sequential.push_back(clip->read(frame));
  }
  EXPECT_NE(sequential[3].rgba, sequential[4].rgba) << "the plate moves: frames differ";
  auto clip = openClip(test::exampleClip().string());
  Image last = clip->read(47);
  EXPECT_EQ(last.width, 768);
  EXPECT_EQ(clip->read(3).rgba, sequential[3].rgba);  // backwards: a seek
  EXPECT_EQ(clip->read(4).rgba, sequential[4].rgba);  // the next frame: no seek
  EXPECT_EQ(clip->read(8).rgba, sequential[8].rgba);  // a small jump forward
  EXPECT_EQ(clip->read(0).rgba, sequential[0].rgba);
}

TEST(ClipReaderMovie, FrameOutsideTheMovieIsAnError) {
  auto clip = openClip(test::exampleClip().string());
  Error e = expectError([&] { clip->read(48); }, test::exampleClip().string());
  EXPECT_EQ(e.context().frame, 48);
  expectError([&] { clip->read(-1); }, "frame -1");
}

TEST(ClipReaderMovie, MovieCutInHalfFailsClearly) {
  auto dir = test::freshTempDir("reader_cut_movie");
  const stdfs::path cut = dir / "half.mp4";
  cutFile(test::exampleClip(), cut, 0.5);  // the example keeps its index at the end: now gone
  expectError([&] { openClip(cut.string()); }, cut.string());
}

TEST(ClipReaderMovie, StreamableMovieCutInHalfReadsFewerFramesOrFailsClearly) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  auto dir = test::freshTempDir("reader_cut_faststart");
  const stdfs::path whole = dir / "faststart.mp4";
  // Index first, so a cut file still opens and claims all 48 frames.
  ASSERT_EQ(runProcess({"ffmpeg", "-v", "error", "-i", test::exampleClip().string(), "-c", "copy",
                        "-movflags", "+faststart", whole.string()})
                .exitCode,
            0);
  const stdfs::path cut = dir / "cut.mp4";
  cutFile(whole, cut, 0.5);
  std::unique_ptr<ClipReader> clip;
  try {
    clip = openClip(cut.string());
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(cut.string()), std::string::npos) << e.what();
    return;
  }
  const ClipInfo& info = clip->info();
  EXPECT_LT(info.frames.size(), 48u) << "frames past the cut cannot be decoded";
  EXPECT_GT(info.frames.size(), 0u);
  for (int64_t frame : info.frames) {
    try {
      EXPECT_EQ(clip->read(frame).width, 768);
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(cut.string()), std::string::npos) << e.what();
      EXPECT_EQ(e.context().frame, frame);
    }
  }
}

TEST(ClipReaderImages, ExrHalfKeepsValuesNanAndInf) {
  auto dir = test::freshTempDir("reader_exr_half");
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::vector<float> samples{0.5f, 2.0f,  -0.25f,   1.0f,          nan,     inf,
                             -inf, 0.75f, 65504.0f, 0.0009765625f, 1024.0f, 0.0f};
  writeSamples(dir / "hdr.0001.exr", 3, 1, 4, OIIO::TypeDesc::HALF, samples);
  auto clip = openClip((dir / "hdr.####.exr").string());
  EXPECT_TRUE(clip->info().isFloat);
  EXPECT_EQ(clip->info().channels, 4);
  Image image = clip->read(1);
  for (size_t i = 0; i < samples.size(); ++i) {
    if (std::isnan(samples[i])) {
      EXPECT_TRUE(std::isnan(image.rgba[i])) << i;
    } else {
      EXPECT_EQ(image.rgba[i], samples[i]) << i;
    }
  }
}

TEST(ClipReaderImages, ExrFloatIsBitExact) {
  auto dir = test::freshTempDir("reader_exr_float");
  std::vector<float> samples{1e-7f, 123456.789f, 0.1f, 3.14159265f, -1e30f, 1.0f / 3.0f};
  writeSamples(dir / "f.exr", 2, 1, 3, OIIO::TypeDesc::FLOAT, samples);
  auto clip = openClip((dir / "f.exr").string());
  EXPECT_TRUE(clip->info().isFloat);
  EXPECT_EQ(clip->info().frames, std::vector<int64_t>{0});
  Image image = clip->read(0);
  for (int p = 0; p < 2; ++p) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(image.rgba[p * 4 + c], samples[p * 3 + c]);
    EXPECT_EQ(image.rgba[p * 4 + 3], 1.0f);
  }
}

// Integer files: every code comes back as code / max exactly; with alpha, colour under alpha 0.2
// stays as stored (not premultiplied on the way in).
struct IntegerFile {
  const char* name;  // the test's, and its folder's
  const char* extension;
  int channels;
  OIIO::TypeDesc type;
  int levels;  // the largest code
};

class ClipReaderIntegerFiles : public ::testing::TestWithParam<IntegerFile> {};

TEST_P(ClipReaderIntegerFiles, EveryCodeIsCodeOverMax) {
  const IntegerFile& file = GetParam();
  const stdfs::path path =
      test::freshTempDir(std::string("reader_") + file.name) / (std::string("a.") + file.extension);
  const int width = 7, height = 5, channels = file.channels;
  std::vector<float> samples = ramp(width, height, channels, file.levels);
  writeSamples(path, width, height, channels, file.type, samples);
  auto clip = openClip(path.string());
  EXPECT_FALSE(clip->info().isFloat);
  EXPECT_EQ(clip->info().channels, channels);
  Image image = clip->read(0);
  ASSERT_EQ(image.width, width);
  ASSERT_EQ(image.height, height);
  for (size_t p = 0; p < image.pixelCount(); ++p) {
    for (int c = 0; c < 3; ++c)
      EXPECT_FLOAT_EQ(image.rgba[p * 4 + c], samples[p * channels + c]) << p;
    EXPECT_FLOAT_EQ(image.rgba[p * 4 + 3], channels == 4 ? samples[p * channels + 3] : 1.0f) << p;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Formats, ClipReaderIntegerFiles,
    ::testing::Values(IntegerFile{"Png8BitRgb", "png", 3, OIIO::TypeDesc::UINT8, 255},
                      IntegerFile{"Png16BitRgb", "png", 3, OIIO::TypeDesc::UINT16, 65535},
                      IntegerFile{"PngRgbaKeepsStraightAlpha", "png", 4, OIIO::TypeDesc::UINT8,
                                  255},
                      IntegerFile{"Tiff16Bit", "tif", 4, OIIO::TypeDesc::UINT16, 65535}),
    [](const ::testing::TestParamInfo<IntegerFile>& info) { return std::string(info.param.name); });

TEST(ClipReaderImages, GrayscalePngIsExpandedToRgb) {
  const stdfs::path path = test::freshTempDir("reader_gray") / "g.png";
  writeSamples(path, 2, 2, 1, OIIO::TypeDesc::UINT8, {0.0f, 64 / 255.0f, 128 / 255.0f, 1.0f});
  auto clip = openClip(path.string());
  EXPECT_EQ(clip->info().channels, 1);
  Image image = clip->read(0);
  const float expected[4] = {0.0f, 64 / 255.0f, 128 / 255.0f, 1.0f};
  for (int p = 0; p < 4; ++p) {
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(image.rgba[p * 4 + c], expected[p]);
    EXPECT_EQ(image.rgba[p * 4 + 3], 1.0f);
  }
}

TEST(ClipReaderImages, GrayAlphaPng) {
  const stdfs::path path = test::freshTempDir("reader_gray_alpha") / "ga.png";
  writeSamples(path, 2, 1, 2, OIIO::TypeDesc::UINT8,
               {200 / 255.0f, 51 / 255.0f, 10 / 255.0f, 1.0f});
  auto clip = openClip(path.string());
  EXPECT_EQ(clip->info().channels, 2);
  Image image = clip->read(0);
  for (int c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(image.rgba[c], 200 / 255.0f);
    EXPECT_FLOAT_EQ(image.rgba[4 + c], 10 / 255.0f);
  }
  EXPECT_FLOAT_EQ(image.rgba[3], 51 / 255.0f);
  EXPECT_FLOAT_EQ(image.rgba[7], 1.0f);
}

TEST(ClipReaderImages, Dpx10Bit) {
  const stdfs::path path = test::freshTempDir("reader_dpx") / "a.dpx";
  std::vector<float> samples = ramp(4, 3, 3, 1023);
  writeSamples(path, 4, 3, 3, OIIO::TypeDesc::UINT16, samples);
  auto clip = openClip(path.string());
  EXPECT_FALSE(clip->info().isFloat);
  Image image = clip->read(0);
  for (size_t p = 0; p < image.pixelCount(); ++p) {
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(image.rgba[p * 4 + c], samples[p * 3 + c], 0.5 / 1023) << p;
  }
}

TEST(ClipReaderImages, JpegIsCloseToWhatWasWritten) {
  const stdfs::path path = test::freshTempDir("reader_jpeg") / "a.jpg";
  std::vector<float> samples(16 * 16 * 3);
  for (size_t i = 0; i < samples.size(); i += 3)
    samples[i] = 0.8f, samples[i + 1] = 0.4f, samples[i + 2] = 0.2f;
  writeSamples(path, 16, 16, 3, OIIO::TypeDesc::UINT8, samples);
  auto clip = openClip(path.string());
  Image image = clip->read(0);
  auto mean = meanRgb(image);
  EXPECT_NEAR(mean[0], 0.8, 0.02);
  EXPECT_NEAR(mean[1], 0.4, 0.02);
  EXPECT_NEAR(mean[2], 0.2, 0.02);
}

TEST(ClipReaderImages, FloatTiffAndHdrAreFloat) {
  auto dir = test::freshTempDir("reader_float_formats");
  writeSamples(dir / "f.tif", 1, 1, 3, OIIO::TypeDesc::FLOAT, {2.5f, 0.25f, 0.125f});
  writeSamples(dir / "h.hdr", 1, 1, 3, OIIO::TypeDesc::FLOAT, {2.5f, 0.25f, 0.125f});
  for (const char* name : {"f.tif", "h.hdr"}) {
    auto clip = openClip((dir / name).string());
    EXPECT_TRUE(clip->info().isFloat) << name;
    Image image = clip->read(0);
    EXPECT_NEAR(image.rgba[0], 2.5f, 0.02f) << name;
    EXPECT_NEAR(image.rgba[2], 0.125f, 0.002f) << name;
  }
}

TEST(ClipReaderImages, OneByOneAndOddSizes) {
  auto dir = test::freshTempDir("reader_small");
  writeSamples(dir / "one.png", 1, 1, 3, OIIO::TypeDesc::UINT8, {1.0f, 0.0f, 0.5f});
  std::vector<float> odd = ramp(3, 5, 3, 255);
  writeSamples(dir / "odd.exr", 3, 5, 3, OIIO::TypeDesc::FLOAT, odd);
  Image one = openClip((dir / "one.png").string())->read(0);
  ASSERT_EQ(one.width, 1);
  ASSERT_EQ(one.height, 1);
  EXPECT_FLOAT_EQ(one.rgba[2], 128 / 255.0f);
  Image three = openClip((dir / "odd.exr").string())->read(0);
  ASSERT_EQ(three.width, 3);
  ASSERT_EQ(three.height, 5);
  // Row-major, row 0 first: pixel (2, 4) is the last one written.
  EXPECT_EQ(three.pixel(2, 4)[1], odd[(4 * 3 + 2) * 3 + 1]);
  EXPECT_EQ(three.pixel(1, 0)[0], odd[3]);
}

TEST(ClipReaderImages, ExrDataWindowIsPlacedInTheDisplayWindow) {
  const stdfs::path path = test::freshTempDir("reader_data_window") / "crop.exr";
  const float samples[6] = {0.25f, 0.5f, 0.75f, 1.0f, 2.0f, 4.0f};
  test::writeWithSpec(path, test::windowedSpec(2, 1, 3, OIIO::TypeDesc::HALF, 1, 2, 4, 4), samples);
  auto clip = openClip(path.string());
  EXPECT_EQ(clip->info().width, 4);
  EXPECT_EQ(clip->info().height, 4);
  Image image = clip->read(0);
  ASSERT_EQ(image.width, 4);
  EXPECT_EQ(image.pixel(1, 2)[0], 0.25f);
  EXPECT_EQ(image.pixel(2, 2)[2], 4.0f);
  EXPECT_EQ(image.pixel(0, 0)[0], 0.0f);
  EXPECT_EQ(image.pixel(3, 3)[3], 1.0f);
}

// Overscan is kept: the frame is the display window grown to the data window, and the clip says
// where the picture lies in it.
TEST(ClipReaderImages, ExrOverscanIsKeptAroundThePicture) {
  const stdfs::path path = test::freshTempDir("reader_overscan") / "overscan.exr";
  std::vector<float> samples(4 * 3 * 4);
  for (size_t i = 0; i < samples.size(); ++i) samples[i] = static_cast<float>(i);
  // Data window -1..2 x -1..1 around a 2 x 2 display window at the origin.
  test::writeWithSpec(path, test::windowedSpec(4, 3, 4, OIIO::TypeDesc::FLOAT, -1, -1, 2, 2),
                      samples.data());
  auto clip = openClip(path.string());
  EXPECT_EQ(clip->info().width, 4);
  EXPECT_EQ(clip->info().height, 3);
  ASSERT_TRUE(clip->info().displayWindow);
  EXPECT_EQ(*clip->info().displayWindow, (PixelWindow{1, 1, 2, 2}));
  EXPECT_FALSE(clip->info().dataWindow);  // the data window is the whole frame
  Image image = clip->read(0);
  ASSERT_EQ(image.width, 4);
  ASSERT_EQ(image.height, 3);
  // Every data pixel in its place: frame (x, y) is data (x, y).
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x)
      for (int c = 0; c < 4; ++c) EXPECT_EQ(image.pixel(x, y)[c], samples[(y * 4 + x) * 4 + c]);
}

// A sequence whose pixels carry their frame number.
void writeNumberedFrames(const stdfs::path& dir, const std::vector<int64_t>& frames) {
  for (int64_t frame : frames) {
    writeSamples(dir / ("plate." + std::to_string(frame) + ".exr"), 4, 2, 3, OIIO::TypeDesc::FLOAT,
                 std::vector<float>(4 * 2 * 3, static_cast<float>(frame)));
  }
}

TEST(ClipReaderSequence, KeepsFrameNumbersFrom1001) {
  auto dir = test::freshTempDir("reader_seq_1001");
  writeNumberedFrames(dir, {1001, 1002, 1003});
  auto clip = openClip((dir / "plate.####.exr").string());
  const ClipInfo& info = clip->info();
  EXPECT_FALSE(info.isMovie);
  EXPECT_EQ(info.frames, (std::vector<int64_t>{1001, 1002, 1003}));
  EXPECT_EQ(info.files.size(), 3u);
  EXPECT_EQ(info.files[1], (dir / "plate.1002.exr").string());
  EXPECT_EQ(info.width, 4);
  EXPECT_EQ(info.height, 2);
  EXPECT_DOUBLE_EQ(info.fps, 24.0);
  EXPECT_EQ(clip->read(1002).rgba[0], 1002.0f);
  EXPECT_EQ(clip->read(1001).rgba[5], 1001.0f);
}

TEST(ClipReaderSequence, PrintfPatternWorksToo) {
  auto dir = test::freshTempDir("reader_seq_printf");
  writeNumberedFrames(dir, {1001, 1002});
  auto clip = openClip((dir / "plate.%04d.exr").string());
  EXPECT_EQ(clip->info().frames, (std::vector<int64_t>{1001, 1002}));
}

TEST(ClipReaderSequence, GapOpensButReadingTheMissingFrameNamesTheFile) {
  auto dir = test::freshTempDir("reader_seq_gap");
  writeNumberedFrames(dir, {1001, 1002, 1004});
  auto clip = openClip((dir / "plate.####.exr").string());
  EXPECT_EQ(clip->info().frames, (std::vector<int64_t>{1001, 1002, 1004}));
  EXPECT_EQ(clip->read(1004).rgba[0], 1004.0f);
  const std::string missing = (dir / "plate.1003.exr").string();
  Error e = expectError([&] { clip->read(1003); }, missing);
  EXPECT_NE(std::string(e.what()).find("1003"), std::string::npos);
  EXPECT_EQ(e.context().frame, 1003);
  expectError([&] { clip->read(1005); }, (dir / "plate.1005.exr").string());
}

TEST(ClipReaderSequence, FrameOfAnotherSizeIsAnError) {
  auto dir = test::freshTempDir("reader_seq_size");
  writeNumberedFrames(dir, {1, 2});
  writeSamples(dir / "plate.3.exr", 5, 2, 3, OIIO::TypeDesc::FLOAT,
               std::vector<float>(5 * 2 * 3, 3.0f));
  auto clip = openClip((dir / "plate.#.exr").string());
  Error e = expectError([&] { clip->read(3); }, "5x2");
  EXPECT_NE(std::string(e.what()).find("4x2"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("frame 3"), std::string::npos) << e.what();
  EXPECT_EQ(e.context().frame, 3);
}

TEST(ClipReaderSequence, PatternWithoutFilesNamesThePattern) {
  auto dir = test::freshTempDir("reader_seq_empty");
  const std::string pattern = (dir / "nothing.####.exr").string();
  expectError([&] { openClip(pattern); }, pattern);
}

TEST(ClipReaderErrors, MissingPathAndFolder) {
  auto dir = test::freshTempDir("reader_missing");
  const std::string missing = (dir / "nope.exr").string();
  expectError([&] { openClip(missing); }, "input not found: " + missing);
  expectError([&] { openClip((dir / "nope.mp4").string()); }, "input not found");
  expectError([&] { openClip(dir.string()); }, "folder");
}

TEST(ClipReaderErrors, TruncatedAndEmptyFilesNameTheFile) {
  auto dir = test::freshTempDir("reader_truncated");
  std::vector<float> samples = ramp(64, 64, 3, 255);
  for (const char* name : {"whole.png", "whole.exr"}) {
    writeSamples(dir / name, 64, 64, 3, OIIO::TypeDesc::UINT8, samples);
    const stdfs::path cut = dir / ("cut." + stdfs::path(name).extension().string().substr(1));
    cutFile(dir / name, cut, 0.5);
    // The header may survive the cut: then reading the pixels must fail.
    expectError([&] { openClip(cut.string())->read(0); }, cut.string());
  }
  std::ofstream(dir / "empty.exr").close();
  expectError([&] { openClip((dir / "empty.exr").string()); }, (dir / "empty.exr").string());
}

TEST(ClipReaderErrors, CorruptFrameInASequenceNamesFileAndFrame) {
  auto dir = test::freshTempDir("reader_seq_corrupt");
  writeNumberedFrames(dir, {1, 2});
  std::ofstream(dir / "plate.3.exr") << "not an exr";
  auto clip = openClip((dir / "plate.#.exr").string());
  Error e = expectError([&] { clip->read(3); }, (dir / "plate.3.exr").string());
  EXPECT_EQ(e.context().frame, 3);
}

TEST(ClipReaderShared, RealRainJpegSequence) {
  if (test::sharedData().empty()) GTEST_SKIP() << "shared data not available";
  const stdfs::path folder = test::sharedData() / "rain_real/nturain_ra1_real_rain_panning";
  if (!stdfs::is_directory(folder)) GTEST_SKIP() << folder << " not available";
  auto clip = openClip((folder / "%05d.jpg").string());
  const ClipInfo& info = clip->info();
  ASSERT_EQ(info.frames.size(), 60u);
  EXPECT_EQ(info.frames.front(), 1);
  EXPECT_EQ(info.frames.back(), 60);
  EXPECT_EQ(info.width, 640);
  EXPECT_EQ(info.height, 480);
  EXPECT_FALSE(info.isFloat);
  Image last = clip->read(60);
  auto mean = meanRgb(last);
  EXPECT_GT(mean[0], 0.02);
  EXPECT_LT(mean[0], 0.98);
}

}  // namespace
}  // namespace pluvia
