// Movies decoded by ffmpeg at their own bit depth, and variable-rate movies conformed to their
// nominal rate. The inputs are small clips ffmpeg makes here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "io/clip_reader.h"
#include "test_support.h"
#include "util/error.h"
#include "util/subprocess.h"

namespace pluvia {
namespace {
namespace stdfs = std::filesystem;

void ffmpeg(std::vector<std::string> args) {
  args.insert(args.begin(), {"ffmpeg", "-v", "error", "-y"});
  const ProcessResult result = runProcess(args);
  ASSERT_EQ(result.exitCode, 0) << result.output;
}

// A dark grey ramp (code 16 to 48 of 255 across 512 pixels, made at 16 bits) as 12-bit ProRes
// 4444: 8 bits hold 33 levels of it, 12 bits up to 16 times as many.
stdfs::path deepRamp(const stdfs::path& dir) {
  constexpr int kWidth = 512, kHeight = 8;
  std::vector<uint16_t> samples;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const double code8 = 16.0 + 32.0 * x / (kWidth - 1);
      const auto value = static_cast<uint16_t>(std::lround(code8 / 255.0 * 65535.0));
      samples.insert(samples.end(), {value, value, value});
    }
  }
  const stdfs::path raw = dir / "ramp.rgb48le";
  std::ofstream(raw, std::ios::binary)
      .write(reinterpret_cast<const char*>(samples.data()),
             static_cast<std::streamsize>(samples.size() * sizeof(uint16_t)));
  const stdfs::path path = dir / "deep.mov";
  ffmpeg({"-f", "rawvideo", "-pix_fmt", "rgb48le", "-s", "512x8", "-r", "10", "-i", raw.string(),
          "-vf", "format=yuv444p12le", "-c:v", "prores_ks", "-profile:v", "4444", path.string()});
  return path;
}

std::set<float> greenLevelsOfRow(const Image& image, int y) {
  std::set<float> levels;
  for (int x = 0; x < image.width; ++x) levels.insert(image.pixel(x, y)[1]);
  return levels;
}

TEST(MovieReader, TwelveBitProResKeepsMoreThanEightBitsOfGradient) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  auto dir = test::freshTempDir("movie_deep_prores");
  auto clip = openClip(deepRamp(dir).string());
  EXPECT_EQ(clip->info().bitsPerSample, 12);
  EXPECT_EQ(clip->info().frames.size(), 1u);
  const Image frame = clip->read(0);
  ASSERT_EQ(frame.width, 512);
  const std::set<float> levels = greenLevelsOfRow(frame, 4);
  // 8 bits would give at most 33 levels over this ramp (every value k/255).
  EXPECT_GT(levels.size(), 4u * 33u) << "levels: " << levels.size();
  int offGrid = 0;
  for (float v : levels) offGrid += std::abs(v * 255.0f - std::round(v * 255.0f)) > 0.05f;
  EXPECT_GT(offGrid, static_cast<int>(levels.size()) / 2);
  // The ramp is the one asked for: 16/255 at the left, 48/255 at the right (within 1 code),
  // rising.
  EXPECT_NEAR(frame.pixel(0, 4)[1], 16.0f / 255.0f, 1.5f / 255.0f);
  EXPECT_NEAR(frame.pixel(511, 4)[1], 48.0f / 255.0f, 1.5f / 255.0f);
  EXPECT_LT(frame.pixel(100, 4)[1], frame.pixel(400, 4)[1]);
}

// A 10-bit ProRes 422 HQ grey ramp, Y' codes 4 to 1019 (sub-blacks below 64, super-whites above
// 940), neutral chroma: read as R' = G' = B' = (Y' / 4 - 16) / 219 exactly, beyond [0, 1] where
// the codes are. Through swscale's rgb48 it read 0.39 % dark (Y' 513: 0.51058 for 0.51256) and
// clipped both ends.
TEST(MovieReader, TenBitYcbcrIsReadAtFullPrecisionAndRange) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  auto dir = test::freshTempDir("movie_ten_bit");
  constexpr int kWidth = 256, kHeight = 4;
  std::vector<uint16_t> planes;
  std::vector<int> codes;
  for (int x = 0; x < kWidth; ++x) codes.push_back(4 + (1019 - 4) * x / (kWidth - 1));
  for (int y = 0; y < kHeight; ++y) planes.insert(planes.end(), codes.begin(), codes.end());
  planes.insert(planes.end(), size_t(kWidth) * kHeight, uint16_t(512));  // Cb, Cr at 4:2:2
  const stdfs::path raw = dir / "ramp.yuv", movie = dir / "ramp.mov";
  std::ofstream(raw, std::ios::binary)
      .write(reinterpret_cast<const char*>(planes.data()),
             static_cast<std::streamsize>(planes.size() * sizeof(uint16_t)));
  ffmpeg({"-f", "rawvideo", "-pix_fmt", "yuv422p10le", "-s", "256x4", "-r", "24", "-i",
          raw.string(), "-c:v", "prores_ks", "-profile:v", "3", "-color_range", "tv", "-colorspace",
          "bt709", movie.string()});
  auto clip = openClip(movie.string());
  EXPECT_EQ(clip->info().bitsPerSample, 10);
  const Image frame = clip->read(0);
  double largest = 0.0;
  for (int x = 0; x < kWidth; ++x) {
    const float expected = (float(codes[size_t(x)]) / 4.0f - 16.0f) / 219.0f;
    for (int c = 0; c < 3; ++c)
      largest = std::max(largest, double(std::fabs(frame.pixel(x, 2)[c] - expected)));
  }
  // ProRes is lossy, but a flat-chroma ramp comes back to a fraction of a 10-bit code.
  EXPECT_LT(largest, 0.5 / 876.0) << "largest error " << largest;
  EXPECT_LT(frame.pixel(0, 2)[1], -0.06f);          // sub-black code 4: -0.0685
  EXPECT_GT(frame.pixel(kWidth - 1, 2)[1], 1.08f);  // super-white 1019: 1.0902
}

// Each code looked up in a table as it is unpacked (readCodesThrough) gives the table's entry
// for the code read() normalises, in every channel, for an 8-bit RGB movie (PNG in QuickTime).
// A Y'CbCr movie (the 8-bit H.264 example, a 12-bit ProRes) is converted by the reader itself,
// beyond [0, 1]: it has no code table (codeBits 0) and reads through one as read() does.
TEST(MovieReader, CodesReadThroughATableAreTheTablesEntries) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  auto dir = test::freshTempDir("movie_code_table");
  for (const stdfs::path& path : {deepRamp(dir), test::exampleClip()}) {
    auto ycbcr = openClip(path.string());
    EXPECT_EQ(ycbcr->codeBits(), 0) << path;
    CodeValues none;
    EXPECT_EQ(ycbcr->readCodesThrough(0, none).rgba, ycbcr->read(0).rgba) << path;
  }
  const stdfs::path rgb = dir / "rgb.mov";
  ffmpeg({"-f", "lavfi", "-i", "testsrc=s=64x36:r=10:d=0.3", "-c:v", "png", "-pix_fmt", "rgb24",
          rgb.string()});
  auto clip = openClip(rgb.string());
  const int bits = clip->codeBits();
  ASSERT_EQ(bits, 8);
  const int largest = (1 << bits) - 1;
  CodeValues table;
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k <= largest; ++k) table[size_t(c)].push_back(float(k) * 3.0f + float(c));
  const Image plain = clip->read(0);
  const Image looked = clip->readCodesThrough(0, table);
  int differing = 0;
  std::set<long> codes;
  for (size_t i = 0; i < plain.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c) {
      const float scaled = plain.rgba[i * 4 + size_t(c)] * float(largest);
      const long code = std::lround(scaled);
      ASSERT_NEAR(scaled, float(code), 1e-3) << "an 8-bit RGB movie gives 8-bit codes";
      codes.insert(code);
      differing += looked.rgba[i * 4 + size_t(c)] != table[size_t(c)][size_t(code)];
    }
  EXPECT_GT(codes.size(), 8u) << "testsrc has colours";
  EXPECT_EQ(differing, 0);
  EXPECT_EQ(looked.rgba[3], 1.0f);
}

// An 8-bit grey ramp, Y' codes 1 to 254 (sub-blacks below 16, super-whites above 235), neutral
// chroma, lossless FFV1: read as R' = G' = B' = (Y' - 16) / 219 exactly, beyond [0, 1] where the
// codes are. Through swscale's rgb24 both ends were clipped to 0 and 1.
TEST(MovieReader, EightBitYcbcrIsReadAtItsCodesAndRange) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  auto dir = test::freshTempDir("movie_eight_bit");
  constexpr int kWidth = 254, kHeight = 4;
  std::vector<uint8_t> planes;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) planes.push_back(uint8_t(1 + x));
  planes.insert(planes.end(), size_t(2 * kWidth * kHeight), uint8_t(128));  // Cb, Cr at 4:4:4
  const stdfs::path raw = dir / "ramp.yuv", movie = dir / "ramp.mkv";
  std::ofstream(raw, std::ios::binary)
      .write(reinterpret_cast<const char*>(planes.data()), std::streamsize(planes.size()));
  ffmpeg({"-f", "rawvideo", "-pix_fmt", "yuv444p", "-s", "254x4", "-r", "24", "-i", raw.string(),
          "-c:v", "ffv1", "-color_range", "tv", "-colorspace", "bt709", movie.string()});
  auto clip = openClip(movie.string());
  EXPECT_EQ(clip->info().bitsPerSample, 8);
  const Image frame = clip->read(0);
  double largest = 0.0;
  for (int x = 0; x < kWidth; ++x) {
    const float expected = (float(1 + x) - 16.0f) / 219.0f;
    for (int c = 0; c < 3; ++c)
      largest = std::max(largest, double(std::fabs(frame.pixel(x, 2)[c] - expected)));
  }
  EXPECT_LT(largest, 1e-5) << "largest error " << largest;
  EXPECT_LT(frame.pixel(0, 2)[1], -0.068f);          // sub-black code 1: -0.0685
  EXPECT_GT(frame.pixel(kWidth - 1, 2)[1], 1.086f);  // super-white 254: 1.0868
}

// Y' 81, Cb 90, Cr 240 is BT.601's red (R'G'B' 1, 0, 0). An untagged movie is BT.601 at standard
// definition and BT.709 above, as players take it (swscale takes both as BT.601): the same codes
// in an untagged 1280x720 movie are BT.709's R' = E'y + 1.5748 E'r.
TEST(MovieReader, AnUntaggedMovieTakesItsMatrixFromItsSize) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  auto dir = test::freshTempDir("movie_untagged_matrix");
  for (const auto& [width, height] : {std::pair{64, 36}, std::pair{1280, 720}}) {
    const size_t plane = size_t(width) * size_t(height);
    std::vector<uint8_t> planes(plane, 81);
    planes.insert(planes.end(), plane, 90);
    planes.insert(planes.end(), plane, 240);
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    const stdfs::path raw = dir / (size + ".yuv"), movie = dir / (size + ".mkv");
    std::ofstream(raw, std::ios::binary)
        .write(reinterpret_cast<const char*>(planes.data()), std::streamsize(planes.size()));
    ffmpeg({"-f", "rawvideo", "-pix_fmt", "yuv444p", "-s", size, "-r", "24", "-i", raw.string(),
            "-c:v", "ffv1", movie.string()});
    const Image frame = openClip(movie.string())->read(0);
    const float* p = frame.pixel(width / 2, height / 2);
    const float ey = (81.0f - 16.0f) / 219.0f, eb = (90.0f - 128.0f) / 224.0f,
                er = (240.0f - 128.0f) / 224.0f;
    if (height <= 576) {
      EXPECT_NEAR(p[0], 1.0f, 0.01f) << size;
      EXPECT_NEAR(p[1], 0.0f, 0.01f) << size;
      EXPECT_NEAR(p[2], 0.0f, 0.01f) << size;
    } else {
      const float r = ey + 1.5748f * er, b = ey + 1.8556f * eb;
      EXPECT_NEAR(p[0], r, 1e-4f) << size;
      EXPECT_NEAR(p[1], (ey - 0.2126f * r - 0.0722f * b) / 0.7152f, 1e-4f) << size;
      EXPECT_NEAR(p[2], b, 1e-4f) << size;
    }
  }
}

// An AVI whose index lists 37 frames at 10 fps, of which only 11 are coded (frames 0-4, then
// every 6th): the others are empty "hold the last frame" entries, as capture tools write
// when they drop frames. Decoded frame by frame it is 11 frames and its timing is lost.
TEST(MovieReader, VariableRateAviIsConformedToItsNominalRate) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  auto dir = test::freshTempDir("movie_vfr");
  const stdfs::path avi = dir / "vfr.avi";
  ffmpeg({"-f", "lavfi", "-i", "testsrc=s=64x36:r=10:d=4", "-vf",
          "select='not(mod(n\\,6))+lt(n\\,5)'", "-fps_mode", "passthrough", "-c:v", "cinepak",
          avi.string()});
  auto clip = openClip(avi.string());
  const ClipInfo& info = clip->info();
  EXPECT_DOUBLE_EQ(info.fps, 10.0);
  ASSERT_EQ(info.frames.size(), 37u);
  std::vector<Image> frames;
  for (int64_t f = 0; f < 37; ++f) frames.push_back(clip->read(f));
  // Coded frames differ (testsrc's counter moves); held frames repeat the last coded one.
  EXPECT_NE(frames[3].rgba, frames[4].rgba);
  EXPECT_NE(frames[4].rgba, frames[6].rgba);
  for (int64_t f : {5}) EXPECT_EQ(frames[f].rgba, frames[4].rgba) << f;
  for (int64_t f : {7, 8, 11}) EXPECT_EQ(frames[f].rgba, frames[6].rgba) << f;
  EXPECT_NE(frames[12].rgba, frames[11].rgba);
  EXPECT_EQ(frames[36].rgba, frames[36 - 36 % 6].rgba);
  // Random access gives the same frames as reading in order.
  EXPECT_EQ(clip->read(30).rgba, frames[30].rgba);
  EXPECT_EQ(clip->read(9).rgba, frames[9].rgba);
}

// A Matroska file at a variable rate: 20 frames, the first 10 a tenth of a second apart, the
// rest three tenths. Matroska lists no frame count and states its nominal rate as its average,
// so the rate looked constant and the 20th frame was "truncated or corrupt"; it is conformed to
// 10 fps as 38 frames, each coded frame held until the next.
TEST(MovieReader, VariableRateMatroskaIsConformedToItsNominalRate) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  auto dir = test::freshTempDir("movie_vfr_mkv");
  const stdfs::path mkv = dir / "vfr.mkv";
  ffmpeg({"-f", "lavfi", "-i", "testsrc=s=64x36:r=10", "-frames:v", "20", "-vf",
          "setpts='(if(lt(N,10),N,10+(N-10)*3))/10/TB'", "-fps_mode", "vfr", "-c:v", "libx264",
          "-pix_fmt", "yuv444p", "-qp", "0", mkv.string()});
  auto clip = openClip(mkv.string());
  ASSERT_EQ(clip->info().frames.size(), 38u);
  std::vector<Image> frames;
  for (int64_t f = 0; f < 38; ++f) frames.push_back(clip->read(f));
  EXPECT_NE(frames[9].rgba, frames[10].rgba);
  // Coded frame 11 is shown at 1.3 s: frames 10-12 hold coded frame 10.
  EXPECT_EQ(frames[11].rgba, frames[10].rgba);
  EXPECT_EQ(frames[12].rgba, frames[10].rgba);
  EXPECT_NE(frames[13].rgba, frames[12].rgba);
  // The last coded frame is shown at 3.7 s, the one before at 3.4 s (frames 34-36).
  EXPECT_EQ(frames[36].rgba, frames[34].rgba);
  EXPECT_NE(frames[37].rgba, frames[36].rgba);
}

TEST(MovieReader, SeekingLandsOnTheFrameAskedFor) {
  auto clip = openClip(test::exampleClip().string());
  std::vector<Image> sequential;
  for (int64_t f = 0; f < 48; ++f) sequential.push_back(clip->read(f));
  auto seeking = openClip(test::exampleClip().string());
  for (int64_t f : {47, 20, 1, 33, 0, 46})
    EXPECT_EQ(seeking->read(f).rgba, sequential[f].rgba) << f;
}

// Frames decoded ahead in one pass (the still's spread frames) are the frames read one by one,
// and a read that was not prefetched, or a list prefetch() cannot take, reads as before.
TEST(MovieReader, PrefetchedFramesAreTheFramesReadOneByOne) {
  auto clip = openClip(test::exampleClip().string());
  std::vector<Image> sequential;
  for (int64_t f = 0; f < 48; ++f) sequential.push_back(clip->read(f));
  // A copy removed once prefetched: its frames can then come only from what prefetch() holds.
  const std::filesystem::path copy = test::freshTempDir("prefetch") / "plate.mp4";
  std::filesystem::copy_file(test::exampleClip(), copy);
  auto held = openClip(copy.string());
  held->prefetch({0, 9, 19, 28, 38});
  std::filesystem::remove(copy);
  for (int64_t f : {0, 9, 19, 28, 38})
    EXPECT_EQ(held->read(f).rgba, sequential[size_t(f)].rgba) << f;
  EXPECT_THROW(held->read(40), Error);  // not prefetched, and the file is gone

  auto ahead = openClip(test::exampleClip().string());
  ahead->prefetch({0, 9, 19, 28, 38});
  for (int64_t f : {0, 9, 40, 3}) EXPECT_EQ(ahead->read(f).rgba, sequential[size_t(f)].rgba) << f;
  ahead->prefetch({47, 2});   // not increasing: ignored
  ahead->prefetch({5, 480});  // past the end: ignored
  for (int64_t f : {47, 2, 5}) EXPECT_EQ(ahead->read(f).rgba, sequential[size_t(f)].rgba) << f;
}

// A process remembers the frame counts it has checked (a render opens its input twice), by
// path, size and modification time: a movie written again under the same name is counted again.
TEST(MovieReader, AMovieWrittenAgainIsCountedAgain) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  auto dir = test::freshTempDir("movie_count_again");
  const stdfs::path path = dir / "clip.mp4";
  auto make = [&](int frames) {
    ffmpeg({"-f", "lavfi", "-i", "testsrc2=s=64x48:r=10", "-frames:v", std::to_string(frames),
            "-c:v", "libx264", "-pix_fmt", "yuv420p", path.string()});
  };
  make(12);
  EXPECT_EQ(openClip(path.string())->info().frames.size(), 12u);
  EXPECT_EQ(openClip(path.string())->info().frames.size(), 12u);
  make(5);
  EXPECT_EQ(openClip(path.string())->info().frames.size(), 5u);
  // And one cut short after it was counted is found out, not read by its old count.
  make(40);
  EXPECT_EQ(openClip(path.string())->info().frames.size(), 40u);
  stdfs::resize_file(path, stdfs::file_size(path) / 2);
  EXPECT_THROW(openClip(path.string())->read(39), Error);
}

// The real vtest AVI of ../shared/data cut to its first 20 kB: its header still lists 795 frames
// but its duration is 0.2 s and one frame is coded. That is a truncated file, not an AVI holding
// frames at a variable rate: it was read as one frame (and the render exited 0, the other 794
// frames lost in silence); now reading it fails naming the file.
TEST(MovieReader, AnAviCutShortIsTruncatedNotVariableRate) {
  const stdfs::path data = test::sharedData();
  if (data.empty()) GTEST_SKIP() << "../shared/data is absent";
  auto dir = test::freshTempDir("movie_cut_avi");
  const stdfs::path cut = dir / "cut.avi";
  {
    std::ifstream in(data / "plate_static/opencv_vtest.avi", std::ios::binary);
    std::vector<char> head(20000);
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    std::ofstream(cut, std::ios::binary).write(head.data(), in.gcount());
  }
  test::expectError(
      [&] {
        auto clip = openClip(cut.string());
        for (int64_t frame : clip->info().frames) clip->read(frame);
      },
      "cut.avi is truncated or corrupt");
}

TEST(MovieReader, NotAMovieNamesTheFile) {
  auto dir = test::freshTempDir("movie_not_a_movie");
  const stdfs::path fake = dir / "fake.mov";
  test::writeTextFile(dir, "fake.mov", "this is not a movie");
  try {
    openClip(fake.string());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(fake.string()), std::string::npos) << e.what();
  }
}

// A camera's shutter tags (QuickTime metadata, names differing by maker) are read as the shutter
// the plate states: an angle, and a speed as a fraction of a second.
TEST(MovieReader, ShutterTagsAreTheStatedShutter) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  auto dir = test::freshTempDir("movie_shutter_tags");
  const stdfs::path angle = dir / "angle.mov", speed = dir / "speed.mov";
  ffmpeg({"-f", "lavfi", "-i", "testsrc2=s=64x48:r=24", "-frames:v", "3", "-movflags",
          "use_metadata_tags", "-metadata", "shutter_angle=172.8", angle.string()});
  ffmpeg({"-f", "lavfi", "-i", "testsrc2=s=64x48:r=24", "-frames:v", "3", "-movflags",
          "use_metadata_tags", "-metadata", "com.sony.shutter_speed=1/100", speed.string()});
  EXPECT_EQ(openClip(angle.string())->info().metadata.at("ShutterAngle"), "172.8");
  EXPECT_EQ(openClip(speed.string())->info().metadata.at("ExposureTime"), "0.01");
}

}  // namespace
}  // namespace pluvia
