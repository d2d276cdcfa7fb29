// End-to-end: the facility's ways in and out (issue 19): "@" patterns and stepped frame lists,
// deep movie input, ProRes/DNxHR output with colour tags, EXR options and pass-through, OCIO
// configs, and the log a wrangler reads.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include <OpenImageIO/imageio.h>

#include "oiio_files.h"
#include "test_support.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

// A small textured plate sequence, frames first..last, written as PNG.
std::string writePlate(const stdfs::path& dir, int first, int last, int w = 64, int h = 36) {
  return test::writeTexturedPlate(dir, first, last, w, h);
}

// A 4x4 PNG of pure red (255, 0, 0): dir/red.png.
std::string writeImageRed(const stdfs::path& dir) {
  Image red(4, 4);
  for (size_t i = 0; i < red.pixelCount(); ++i) {
    red.rgba[i * 4] = 1.0f;
    red.rgba[i * 4 + 3] = 1.0f;
  }
  test::writeImageFile(dir / "red.png", red);
  return (dir / "red.png").string();
}

// "dir/plate.####.png" -> "dir/plate.@@@@.png"
std::string withAtSigns(std::string pattern) {
  for (char& c : pattern)
    if (c == '#') c = '@';
  return pattern;
}

}  // namespace

TEST(CliIo, AtPatternsAndASteppedFrameList) {
  auto dir = freshTempDir("cli_io_stepped");
  const std::string plate = withAtSigns(writePlate(dir, 1001, 1009));
  const std::string out = (dir / "out.@@@@.png").string();
  auto r = runPluvia({"render", plate, "-p", "moderate", "-o", out, "--frames", "1001-1009x4"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (int f = 1001; f <= 1009; ++f) {
    const bool asked = (f - 1001) % 4 == 0;
    EXPECT_EQ(stdfs::exists(dir / ("out." + std::to_string(f) + ".png")), asked) << f;
  }
  // With no rain, fog, blur or darkening each frame written is its own plate frame, code for
  // code (not the 1st, 2nd and 3rd frames of the clip).
  r = runPluvia({"render", plate, "-p", "moderate", "-o", (dir / "same.@@@@.png").string(),
                 "--frames", "1001-1009x4", "--set", "rain.rate_mm_h=0", "--set", "fog.density=0",
                 "--set", "blur.sigma_px=0", "--set", "darken.amount=0"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (int f : {1001, 1005, 1009})
    EXPECT_EQ(readImageFile(dir / ("same." + std::to_string(f) + ".png")).rgba,
              readImageFile(dir / ("plate." + std::to_string(f) + ".png")).rgba)
        << f;
}

TEST(CliIo, CommaListNamesAFrameTheClipLacks) {
  auto dir = freshTempDir("cli_io_comma");
  const std::string plate = writePlate(dir, 1, 3);
  auto r = runPluvia(
      {"render", plate, "-p", "drizzle", "-o", (dir / "o.####.png").string(), "--frames", "1,3,7"});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("frame 7 of --frames is not in"), std::string::npos) << r.output;
  EXPECT_FALSE(stdfs::exists(dir / "o.0001.png"));
  r = runPluvia(
      {"render", plate, "-p", "drizzle", "-o", (dir / "o.####.png").string(), "--frames", "1-3x0"});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("'1-3x0'"), std::string::npos) << r.output;
}

namespace {

std::map<std::string, std::string> ffprobeStream(const stdfs::path& movie) {
  const ProcessResult probe =
      runProcess({"ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries",
                  "stream=codec_name,profile,pix_fmt,color_primaries,color_transfer,color_space,"
                  "color_range:stream_tags=timecode",
                  "-of", "default=noprint_wrappers=1", movie.string()});
  std::map<std::string, std::string> fields;
  std::istringstream lines(probe.output);
  for (std::string line; std::getline(lines, line);) {
    const size_t equals = line.find('=');
    if (equals != std::string::npos) fields[line.substr(0, equals)] = line.substr(equals + 1);
  }
  return fields;
}

}  // namespace

// A movie's colour tags say how its RGB is encoded (adversarial round: a ProRes tagged BT.709 was
// read as sRGB and written back tagged sRGB): with color.input and color.output auto, a BT.709
// plate is read through the Rec.709 OETF and goes out tagged BT.709, its picture kept; an
// untagged one is read as sRGB, and the log says which.
TEST(CliIo, AMoviesColourTagsAreReadAndWrittenBack) {
  if (!programAvailable("ffprobe")) GTEST_SKIP() << "ffprobe not on PATH";
  auto dir = freshTempDir("cli_io_tags_in");
  auto makeMovie = [&](const stdfs::path& movie, bool tagged) {
    std::vector<std::string> args{"ffmpeg",
                                  "-v",
                                  "error",
                                  "-f",
                                  "lavfi",
                                  "-i",
                                  "testsrc=size=256x144:rate=24",
                                  "-frames:v",
                                  "3",
                                  "-c:v",
                                  "prores_ks",
                                  "-profile:v",
                                  "hq",
                                  "-pix_fmt",
                                  "yuv422p10le"};
    // setparams tags the frames; the muxer writes the tags into the movie.
    if (tagged)
      args.insert(args.end(),
                  {"-vf", "setparams=color_primaries=bt709:color_trc=bt709:colorspace=bt709"});
    args.push_back(movie.string());
    ASSERT_EQ(runProcess(args).exitCode, 0);
  };
  const std::vector<std::string> plateOnly{"--set", "rain.rate_mm_h=0", "--set", "fog.density=0",
                                           "--set", "blur.sigma_px=0",  "--set", "darken.amount=0"};
  makeMovie(dir / "bt709.mov", true);
  std::vector<std::string> args{"render", (dir / "bt709.mov").string(),  "-p",      "moderate",
                                "-o",     (dir / "out709.mov").string(), "--codec", "prores_422hq"};
  args.insert(args.end(), plateOnly.begin(), plateOnly.end());
  auto r = runPluvia(args);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("the movie is tagged bt709 on bt709 primaries: read as rec709"),
            std::string::npos)
      << r.output;
  auto fields = ffprobeStream(dir / "out709.mov");
  EXPECT_EQ(fields["color_transfer"], "bt709");
  EXPECT_EQ(fields["color_primaries"], "bt709");
  EXPECT_EQ(fields["color_space"], "bt709");
  // The picture went through the Rec.709 curve and back: the plate's codes (ProRes twice).
  for (const char* name : {"bt709.mov", "out709.mov"})
    ASSERT_EQ(runProcess({"ffmpeg", "-v", "error", "-i", (dir / name).string(), "-frames:v", "1",
                          "-pix_fmt", "rgb48be", (dir / (std::string(name) + ".png")).string()})
                  .exitCode,
              0);
  Image before = readImageFile(dir / "bt709.mov.png"),
        after = readImageFile(dir / "out709.mov.png");
  ASSERT_EQ(before.rgba.size(), after.rgba.size());
  double sum = 0;
  for (size_t i = 0; i < after.rgba.size(); ++i) sum += std::abs(after.rgba[i] - before.rgba[i]);
  // ProRes 4:2:2 twice: measured 1.5 codes.
  EXPECT_LT(sum / after.rgba.size() * 255, 2.0);

  // A space the user gives for the plate overrides its tags, for the output too.
  args = {"render",
          (dir / "bt709.mov").string(),
          "-p",
          "moderate",
          "-o",
          (dir / "given.mov").string(),
          "--codec",
          "prores_422hq",
          "--in-colorspace",
          "sRGB"};
  args.insert(args.end(), plateOnly.begin(), plateOnly.end());
  r = runPluvia(args);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(ffprobeStream(dir / "given.mov")["color_transfer"], "iec61966-2-1");

  makeMovie(dir / "untagged.mov", false);
  args = {"render", (dir / "untagged.mov").string(), "-p",      "moderate",
          "-o",     (dir / "out.mov").string(),      "--codec", "prores_422hq"};
  args.insert(args.end(), plateOnly.begin(), plateOnly.end());
  r = runPluvia(args);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("the movie has no colour transfer tag: read as sRGB"), std::string::npos)
      << r.output;
  EXPECT_EQ(ffprobeStream(dir / "out.mov")["color_transfer"], "iec61966-2-1");
}

TEST(CliIo, ProResAndDnxhrOutputCarryTheirColourTags) {
  if (!programAvailable("ffprobe")) GTEST_SKIP() << "ffprobe not on PATH";
  auto dir = freshTempDir("cli_io_prores");
  const std::string plate = writePlate(dir, 1, 3);
  // DNxHR's smallest frame.
  stdfs::create_directories(dir / "large");
  const std::string largePlate = writePlate(dir / "large", 1, 2, 256, 120);
  struct Case {
    std::string codec, name, profile, pixelFormat, extension = ".mov";
  };
  for (const Case& c : {Case{"prores_4444", "prores", "4444", "yuv444p12le"},
                        Case{"prores_422hq", "prores", "HQ", "yuv422p10le"},
                        Case{"dnxhr_hqx", "dnxhd", "DNXHR HQX", "yuv422p10le"},
                        // 8-bit: Y'CbCr made by pluvia, only tagged by ffmpeg.
                        Case{"dnxhr_hq", "dnxhd", "DNXHR HQ", "yuv422p"},
                        Case{"h264", "h264", "High", "yuv420p", ".mp4"}}) {
    const stdfs::path movie = dir / (c.codec + c.extension);
    auto r = runPluvia({"render", c.name == "dnxhd" ? largePlate : plate, "-p", "drizzle", "-o",
                        movie.string(), "--codec", c.codec});
    ASSERT_EQ(r.exitCode, 0) << r.output;
    auto fields = ffprobeStream(movie);
    EXPECT_EQ(fields["codec_name"], c.name) << c.codec;
    EXPECT_EQ(fields["profile"], c.profile) << c.codec;
    EXPECT_EQ(fields["pix_fmt"], c.pixelFormat) << c.codec;
    // sRGB-encoded output: Rec.709 primaries and matrix, the sRGB curve, video range.
    EXPECT_EQ(fields["color_primaries"], "bt709") << c.codec;
    EXPECT_EQ(fields["color_transfer"], "iec61966-2-1") << c.codec;
    EXPECT_EQ(fields["color_space"], "bt709") << c.codec;
    EXPECT_EQ(fields["color_range"], "tv") << c.codec;
  }
  // DNxHR in MXF, as Avid and broadcast take it: MXF has no label for the sRGB transfer (the log
  // says so), so a BT.709 output is what it tags fully.
  auto r = runPluvia({"render", largePlate, "-p", "drizzle", "-o", (dir / "dnxhr.mxf").string(),
                      "--codec", "dnxhr_hq"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("MXF has no label for the sRGB transfer"), std::string::npos) << r.output;
  r = runPluvia({"render", largePlate, "-p", "drizzle", "-o", (dir / "dnxhr709.mxf").string(),
                 "--codec", "dnxhr_hq", "--out-colorspace", "rec709"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  auto mxf = ffprobeStream(dir / "dnxhr709.mxf");
  EXPECT_EQ(mxf["codec_name"], "dnxhd");
  EXPECT_EQ(mxf["color_primaries"], "bt709");
  EXPECT_EQ(mxf["color_transfer"], "bt709");
  EXPECT_EQ(mxf["color_space"], "bt709");
  // The decoded frame is the plate (rain aside): RGB went through the tagged matrix and back.
  r = runPluvia({"render", plate, "-p", "moderate", "-o", (dir / "still.mov").string(), "--codec",
                 "prores_4444", "--set", "rain.rate_mm_h=0", "--set", "fog.density=0", "--set",
                 "blur.sigma_px=0", "--set", "darken.amount=0"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  ASSERT_EQ(runProcess({"ffmpeg", "-v", "error", "-i", (dir / "still.mov").string(), "-frames:v",
                        "1", "-pix_fmt", "rgb48be", (dir / "back.png").string()})
                .exitCode,
            0);
  Image back = readImageFile(dir / "back.png"), source = readImageFile(dir / "plate.0001.png");
  // ProRes is lossy and the plate's sawtooth edges ring: measured with ffmpeg 5.1, a mean
  // error of 0.8 codes a sample when converted with the tagged BT.709 matrix, 5.8 codes when
  // converted with ffmpeg's default BT.601 and decoded by the tag.
  double sum = 0;
  for (size_t i = 0; i < back.rgba.size(); ++i) sum += std::abs(back.rgba[i] - source.rgba[i]);
  EXPECT_LT(sum / back.rgba.size() * 255, 2.0);
  // A codec the container cannot hold is refused before any work, naming both.
  r = runPluvia(
      {"render", plate, "-p", "drizzle", "-o", (dir / "x.mp4").string(), "--codec", "prores_4444"});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("prores_4444 does not go into a .mp4"), std::string::npos) << r.output;
  r = runPluvia({"render", plate, "-p", "drizzle", "-o", (dir / "small.mov").string(), "--codec",
                 "dnxhr_hq"});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("at least 256x120"), std::string::npos) << r.output;
}

// An EXR plate with a data window smaller than its frame and a timecode: the output keeps the
// window, and each frame's timecode counts on from the first.
TEST(CliIo, ExrDataWindowTimecodeAndCameraPassThrough) {
  auto dir = freshTempDir("cli_io_exr_window");
  for (int f = 1001; f <= 1002; ++f) {
    OIIO::ImageSpec spec = windowedSpec(40, 20, 3, OIIO::TypeDesc::HALF, 8, 6, 64, 36);
    spec.attribute("compression", "zip");
    const uint32_t timecode[2] = {0x01000010u + static_cast<uint32_t>(f - 1001), 0};  // 01:00:00:10
    spec.attribute("smpte:TimeCode", OIIO::TypeTimeCode, timecode);
    spec.attribute("Make", "ARRI");
    spec.attribute("Model", "ALEXA Mini");
    spec.attribute("ExposureTime", 0.01f);
    spec.attribute("FNumber", 2.8f);
    std::vector<float> pixels(40 * 20 * 3, 0.25f);
    ASSERT_NO_FATAL_FAILURE(
        writeWithSpec(dir / ("plate." + std::to_string(f) + ".exr"), spec, pixels.data()));
  }
  auto r = runPluvia({"-q", "render", (dir / "plate.####.exr").string(), "-p", "drizzle", "-o",
                      (dir / "out.####.exr").string(), "--exr-type", "float", "--exr-compression",
                      "dwaa"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  // No library's debug lines under -q (Debian's OpenImageIO printed "OIIO DEBUG: OpenEXR output
  // metadata "ExposureTime" type mismatch" while the exposure was carried as text).
  EXPECT_EQ(r.output.find("DEBUG"), std::string::npos) << r.output;
  for (int f = 1001; f <= 1002; ++f) {
    auto in = OIIO::ImageInput::open((dir / ("out." + std::to_string(f) + ".exr")).string());
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    EXPECT_EQ(spec.x, 8);
    EXPECT_EQ(spec.y, 6);
    EXPECT_EQ(spec.width, 40);
    EXPECT_EQ(spec.height, 20);
    EXPECT_EQ(spec.full_width, 64);
    EXPECT_EQ(spec.full_height, 36);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(spec.get_string_attribute("compression"), "dwaa");
    EXPECT_EQ(spec.get_string_attribute("Make"), "ARRI");
    EXPECT_EQ(spec.get_string_attribute("Model"), "ALEXA Mini");
    // The exposure fields stay numbers.
    EXPECT_FLOAT_EQ(spec.get_float_attribute("ExposureTime"), 0.01f);
    EXPECT_FLOAT_EQ(spec.get_float_attribute("FNumber"), 2.8f);
    EXPECT_EQ(spec.get_string_attribute("colorspace"), "linear-rec709");
    const OIIO::ParamValue* timecode = spec.find_attribute("smpte:TimeCode");
    ASSERT_TRUE(timecode) << f;
    EXPECT_EQ(static_cast<const uint32_t*>(timecode->data())[0],
              0x01000010u + static_cast<uint32_t>(f - 1001))
        << f;
    // Rec.709 chromaticities for the built-in config's scene-linear space.
    const OIIO::ParamValue* chromaticities = spec.find_attribute("chromaticities");
    ASSERT_TRUE(chromaticities);
    EXPECT_FLOAT_EQ(static_cast<const float*>(chromaticities->data())[0], 0.64f);
    EXPECT_FLOAT_EQ(static_cast<const float*>(chromaticities->data())[7], 0.3290f);
  }
}

// Overscan kept (issue 30): a plate whose data window reaches 8 and 6 px past its 64x36 display
// window renders the overscan too, rain included, and an EXR output keeps both windows; a PNG
// holds the picture alone.
TEST(CliIo, ExrOverscanIsRenderedAndKept) {
  auto dir = freshTempDir("cli_io_exr_overscan");
  constexpr int kWidth = 80, kHeight = 48;
  for (int f = 1; f <= 2; ++f) {
    const OIIO::ImageSpec spec =
        windowedSpec(kWidth, kHeight, 3, OIIO::TypeDesc::HALF, -8, -6, 64, 36);
    std::vector<float> pixels(size_t(kWidth) * kHeight * 3);
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x)
        for (int c = 0; c < 3; ++c)
          pixels[(size_t(y) * kWidth + x) * 3 + c] = 0.05f + 0.002f * float(x + y) + 0.02f * c;
    ASSERT_NO_FATAL_FAILURE(
        writeWithSpec(dir / fmt::format("plate.{}.exr", f), spec, pixels.data()));
  }
  auto r = runPluvia({"render", (dir / "plate.#.exr").string(), "-p", "heavy", "-o",
                      (dir / "out.#.exr").string(), "--exr-type", "float", "--aov", "rain", "--set",
                      "fog.enabled=false", "--set", "darken.enabled=false", "--set",
                      "blur.enabled=false", "--set", "wet_ground.enabled=false"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  auto in = OIIO::ImageInput::open((dir / "out.1.exr").string());
  ASSERT_TRUE(in);
  const OIIO::ImageSpec& spec = in->spec();
  EXPECT_EQ(spec.full_x, 0);
  EXPECT_EQ(spec.full_y, 0);
  EXPECT_EQ(spec.full_width, 64);
  EXPECT_EQ(spec.full_height, 36);
  EXPECT_EQ(spec.x, -8);
  EXPECT_EQ(spec.y, -6);
  EXPECT_EQ(spec.width, kWidth);
  EXPECT_EQ(spec.height, kHeight);
  std::vector<float> out(spec.image_pixels() * size_t(spec.nchannels));
  ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, out.data()));
  const int alpha = spec.channelindex("rain.A"), red = spec.channelindex("R");
  ASSERT_GE(alpha, 0);
  // The overscan holds the plate (its first column, file x = -8) and rain, as the picture does.
  double overscanRain = 0.0, pictureRain = 0.0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const float* p = out.data() + (size_t(y) * kWidth + x) * size_t(spec.nchannels);
      const bool inPicture = x >= 8 && x < 72 && y >= 6 && y < 42;
      (inPicture ? pictureRain : overscanRain) += p[alpha];
      if (x == 0) EXPECT_GE(p[red], 0.05f + 0.002f * float(y) - 1e-3f) << y;
    }
  EXPECT_GT(overscanRain, 0.0);
  EXPECT_GT(pictureRain, 0.0);

  r = runPluvia({"render", (dir / "plate.#.exr").string(), "-p", "heavy", "-o",
                 (dir / "out.#.png").string(), "--frames", "1"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const Image png = readImageFile(dir / "out.1.png");
  EXPECT_EQ(png.width, 64);
  EXPECT_EQ(png.height, 36);
}

// A small ACES-style config (ACES2065-1 reference; ACEScg, linear Rec.709 and sRGB texture
// spaces with aliases; scene_linear = ACEScg), as a facility's $OCIO names it.
static std::string acesStyleConfig() {
  return R"(ocio_profile_version: 2.1
name: aces-style-test
roles:
  scene_linear: ACEScg
  default: ACEScg
  data: Raw
  texture_paint: sRGB - Texture
  aces_interchange: ACES2065-1
file_rules:
  - !<Rule> {name: Default, colorspace: default}
displays:
  sRGB - Display:
    - !<View> {name: Raw, colorspace: Raw}
active_displays: []
active_views: []
colorspaces:
  - !<ColorSpace>
    name: ACES2065-1
    aliases: [aces2065_1, lin_ap0]
    family: ACES
    encoding: scene-linear
  - !<ColorSpace>
    name: ACEScg
    aliases: [lin_ap1, acescg]
    family: ACES
    encoding: scene-linear
    to_scene_reference: !<BuiltinTransform> {style: ACEScg_to_ACES2065-1}
  - !<ColorSpace>
    name: Linear Rec.709 (sRGB)
    aliases: [lin_rec709]
    family: Utility
    encoding: scene-linear
    to_scene_reference: !<GroupTransform>
      children:
        - !<BuiltinTransform> {style: "UTILITY - ACES-AP1_to_LINEAR-REC709_BFD", direction: inverse}
        - !<BuiltinTransform> {style: ACEScg_to_ACES2065-1}
  - !<ColorSpace>
    name: sRGB - Texture
    aliases: [srgb_tex]
    family: Utility
    encoding: sdr-video
    to_scene_reference: !<GroupTransform>
      children:
        - !<ExponentWithLinearTransform> {gamma: 2.4, offset: 0.055}
        - !<BuiltinTransform> {style: "UTILITY - ACES-AP1_to_LINEAR-REC709_BFD", direction: inverse}
        - !<BuiltinTransform> {style: ACEScg_to_ACES2065-1}
  - !<ColorSpace>
    name: Raw
    family: Utility
    isdata: true
)";
}

TEST(CliIo, OcioEnvironmentConfigSetsTheSpacesAndTags) {
  auto dir = freshTempDir("cli_io_ocio");
  const stdfs::path config = writeTextFile(dir, "aces.ocio", acesStyleConfig());
  const ProcessResult check = runProcess({"ociocheck", "--iconfig", config.string()});
  if (check.exitCode != 127) {
    ASSERT_EQ(check.exitCode, 0) << check.output;
  }
  const std::string plate = writePlate(dir, 1, 1);
  auto run = [&](std::vector<std::string> args) {
    std::vector<std::string> argv{"env", "OCIO=" + config.string(), pluviaBinary().string()};
    argv.insert(argv.end(), args.begin(), args.end());
    return runProcess(argv);
  };
  // The plate (sRGB PNG) goes in through the config's "sRGB - Texture", the working space is
  // its scene_linear (ACEScg), and the EXR comes out in it, saying so.
  auto r = run({"render", plate, "-p", "moderate", "-o", (dir / "aces.####.exr").string(), "--set",
                "rain.rate_mm_h=0", "--set", "fog.density=0", "--set", "blur.sigma_px=0", "--set",
                "darken.amount=0"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("(from $OCIO)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("sRGB - Texture -> scene_linear (working) -> scene_linear"),
            std::string::npos)
      << r.output;
  auto in = OIIO::ImageInput::open((dir / "aces.0001.exr").string());
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().get_string_attribute("colorspace"), "ACEScg");
  const OIIO::ParamValue* chromaticities = in->spec().find_attribute("chromaticities");
  ASSERT_TRUE(chromaticities);
  EXPECT_FLOAT_EQ(static_cast<const float*>(chromaticities->data())[0], 0.713f);  // AP1 red x
  // Pure sRGB red (255, 0, 0) in ACEScg is (0.6131, 0.0701, 0.0206) (the Rec.709 to AP1 matrix
  // with Bradford adaptation, as in the ACES config).
  r = run({"render", writeImageRed(dir), "-p", "moderate", "-o", (dir / "red.exr").string(),
           "--set", "rain.rate_mm_h=0", "--set", "fog.density=0", "--set", "blur.sigma_px=0",
           "--set", "darken.amount=0"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  Image red = readImageFile(dir / "red.exr");
  EXPECT_NEAR(red.rgba[0], 0.6131, 2e-3);
  EXPECT_NEAR(red.rgba[1], 0.0701, 2e-3);
  EXPECT_NEAR(red.rgba[2], 0.0206, 2e-3);
  // Aliases name spaces on the command line; the output is in the one asked for.
  r = run({"render", writeImageRed(dir), "-p", "moderate", "-o", (dir / "red709.exr").string(),
           "--in-colorspace", "srgb_tex", "--out-colorspace", "lin_rec709", "--set",
           "rain.rate_mm_h=0", "--set", "fog.density=0", "--set", "blur.sigma_px=0", "--set",
           "darken.amount=0"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  Image red709 = readImageFile(dir / "red709.exr");
  EXPECT_NEAR(red709.rgba[0], 1.0, 2e-3);
  EXPECT_NEAR(red709.rgba[1], 0.0, 2e-3);
  // An unknown name is an error naming it and the config.
  r = run({"render", plate, "-p", "moderate", "-o", (dir / "x.####.exr").string(),
           "--out-colorspace", "no_such_space"});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("'no_such_space'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(config.string()), std::string::npos) << r.output;
}

TEST(CliIo, ProgressLinesQuietAndVerboseAnywhereAndALogFile) {
  auto dir = freshTempDir("cli_io_logs");
  const std::string plate = writePlate(dir, 1, 4);
  const stdfs::path log = dir / "render.log";
  auto r = runPluvia({"render", plate, "-p", "drizzle", "-o", (dir / "o.####.png").string(),
                      "--log", log.string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (int n = 1; n <= 4; ++n) {
    const std::string counted = fmt::format("({}/4, {} %, ETA ", n, 25 * n);
    EXPECT_NE(r.output.find(counted), std::string::npos) << counted << "\n" << r.output;
  }
  EXPECT_NE(r.output.find("progress: frame 4 ("), std::string::npos) << r.output;
  std::ifstream logIn(log);
  const std::string logged((std::istreambuf_iterator<char>(logIn)), {});
  EXPECT_NE(logged.find("progress: frame "), std::string::npos) << logged;
  EXPECT_NE(logged.find("pluvia: command: "), std::string::npos) << logged;
  // -q after the command's options: no progress and no info lines.
  r = runPluvia({"render", plate, "-p", "drizzle", "-o", (dir / "q.####.png").string(), "-q"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(r.output.find("progress:"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("command: "), std::string::npos) << r.output;
  // -v at the end: debug lines appear.
  r = runPluvia({"render", plate, "-p", "drizzle", "-o", (dir / "v.####.png").string(), "-v"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("pluvia: debug: "), std::string::npos) << r.output;
  // A log file that cannot be opened is an error naming it.
  r = runPluvia({"--log", (dir / "no/such/dir/x.log").string(), "render", plate, "-p", "drizzle",
                 "-o", (dir / "n.####.png").string()});
  EXPECT_EQ(r.exitCode, 1) << r.output;
  EXPECT_NE(r.output.find("no/such/dir/x.log"), std::string::npos) << r.output;
}
