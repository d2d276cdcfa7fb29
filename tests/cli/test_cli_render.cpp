// End-to-end: `pluvia render` on the bundled example and on small sequences the tests write.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "test_support.h"
#include "util/fs.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {
const std::string kExamplePreset = (sourceDir() / "examples/street/street.json").string();

double meanAbsDifference(const Image& a, const Image& b) {
  double sum = 0;
  for (size_t i = 0; i < a.rgba.size(); ++i) sum += std::fabs(a.rgba[i] - b.rgba[i]);
  return sum / double(a.rgba.size());
}
}  // namespace

TEST(CliRender, ExampleGetsVisibleRainAndTheStatsTable) {
  auto dir = freshTempDir("render_example");
  auto out = (dir / "rain.####.png").string();
  // The wet ground aside (it darkens where the rain falls, and a render without rain has none).
  auto r = runPluvia({"render", exampleClip().string(), "-p", kExamplePreset, "-o", out, "--frames",
                      "10-12", "--stats", "--set", "wet_ground.enabled=false", "-v"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("rain"), std::string::npos);
  EXPECT_NE(r.output.find("ms/frame"), std::string::npos);             // --stats
  EXPECT_NE(r.output.find("command: "), std::string::npos);            // command line in the log
  EXPECT_NE(r.output.find("preset (resolved): "), std::string::npos);  // -v
  for (int f = 10; f <= 12; ++f)
    EXPECT_TRUE(stdfs::exists(dir / ("rain.00" + std::to_string(f) + ".png")));
  // The same frame without rain: the rain changes many pixels, most of them brighter.
  auto dry = (dir / "dry.####.png").string();
  ASSERT_EQ(runPluvia({"render", exampleClip().string(), "-p", kExamplePreset, "-o", dry,
                       "--frames", "11-11", "--set", "rain.enabled=false"})
                .exitCode,
            0);
  Image wet = readImageFile(dir / "rain.0011.png"), plain = readImageFile(dir / "dry.0011.png");
  size_t brighter = 0, darker = 0;
  for (size_t i = 0; i < wet.pixelCount(); ++i) {
    float d = wet.rgba[i * 4 + 1] - plain.rgba[i * 4 + 1];
    if (d > 2.5f / 255) ++brighter;
    if (d < -2.5f / 255) ++darker;
  }
  EXPECT_GT(brighter, wet.pixelCount() / 50) << "rain should touch at least 2% of the pixels";
  EXPECT_GT(brighter, 3 * darker);
  // No temporary files are left behind.
  for (const auto& e : stdfs::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find("pluvia-tmp"), std::string::npos);
}

TEST(CliRender, NoOpPresetReproducesThePlateExactly) {
  auto dir = freshTempDir("render_identity");
  auto plate = writeTexturedPlate(dir, 1001, 1002);
  auto r = runPluvia({"render", plate, "-p", "moderate", "-o", (dir / "out.####.png").string(),
                      "--set", "rain.rate_mm_h=0", "--set", "fog.density=0", "--set",
                      "blur.sigma_px=0", "--set", "darken.amount=0"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  // Frame numbers are kept, and sRGB in -> linear -> sRGB out returns every 8-bit code.
  Image in = readImageFile(dir / "plate.1002.png"), out = readImageFile(dir / "out.1002.png");
  EXPECT_EQ(in.rgba, out.rgba);
}

TEST(CliRender, ChunksAndThreadCountsGiveIdenticalFrames) {
  auto dir = freshTempDir("render_determinism");
  auto plate = writeTexturedPlate(dir, 1, 6, 96, 64);
  // The whole rain model: a ramped gusty wind with a stable-fluids field, rain cells, spread,
  // and a camera walking forward while it turns.
  const std::vector<std::string> common{
      "-p",
      "heavy",
      "--set",
      "rain.seed=5",
      "--set",
      "camera.exposure_s=0.04",
      "--set",
      "rain.wind.speed_m_s=[[1,2],[6,10]]",
      "--set",
      "rain.wind.turbulence=0.5",
      "--set",
      "rain.wind.gustiness=0.5",
      "--set",
      "rain.cells.count=2",
      "--set",
      "rain.spread_m_s=0.5",
      "--set",
      R"(camera.path=[{"frame":1,"position_m":[0,1.6,0]},{"frame":6,"position_m":[0,1.6,-3],"yaw_deg":10}])"};
  auto run = [&](const std::string& out, const std::string& frames, const std::string& threads) {
    std::vector<std::string> args{"render",   plate,  "-o",        (dir / out).string(),
                                  "--frames", frames, "--threads", threads};
    args.insert(args.end(), common.begin(), common.end());
    auto r = runPluvia(args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
  };
  run("full.####.exr", "1-6", "1");
  run("chunk.####.exr", "1-3", "2");
  run("chunk.####.exr", "4-6", "3");
  run("alone.####.exr", "5-5", "1");
  for (int f = 1; f <= 6; ++f) {
    Image full = readImageFile(dir / ("full.000" + std::to_string(f) + ".exr"));
    Image chunk = readImageFile(dir / ("chunk.000" + std::to_string(f) + ".exr"));
    EXPECT_EQ(full.rgba, chunk.rgba) << "frame " << f;
  }
  EXPECT_EQ(readImageFile(dir / "full.0005.exr").rgba, readImageFile(dir / "alone.0005.exr").rgba);
  // Different frames differ (the rain moves).
  EXPECT_GT(
      meanAbsDifference(readImageFile(dir / "full.0002.exr"), readImageFile(dir / "full.0003.exr")),
      1e-4);
}

TEST(CliRender, SkipExistingResumesWithoutRewriting) {
  auto dir = freshTempDir("render_skip");
  auto plate = writeTexturedPlate(dir, 1, 3);
  auto out = (dir / "out.####.png").string();
  ASSERT_EQ(runPluvia({"render", plate, "-p", "drizzle", "-o", out, "--frames", "1-2"}).exitCode,
            0);
  auto before = stdfs::last_write_time(dir / "out.0001.png");
  auto r = runPluvia({"render", plate, "-p", "drizzle", "-o", out, "--skip-existing"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("2 existing frames skipped"), std::string::npos) << r.output;
  EXPECT_EQ(stdfs::last_write_time(dir / "out.0001.png"), before);
  EXPECT_TRUE(stdfs::exists(dir / "out.0003.png"));
}

// At half size: what is checked (a movie written, the AOVs' channels and metadata) does not
// depend on it.
TEST(CliRender, MovieOutputAndAovs) {
  auto dir = freshTempDir("render_movie");
  auto movie = (dir / "rain.mp4").string();
  auto r = runPluvia({"render", exampleClip().string(), "-p", "drizzle", "-o", movie, "--frames",
                      "0-5", "--proxy", "0.5"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_GT(stdfs::file_size(movie), 1000u);
  auto exr = (dir / "aov.####.exr").string();
  r = runPluvia({"render", exampleClip().string(), "-p", "moderate", "-o", exr, "--frames", "3-3",
                 "--aov", "rain,matte,depth", "--proxy", "0.5"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  auto channels = runProcess({"oiiotool", "--info", "-v", (dir / "aov.0003.exr").string()});
  EXPECT_NE(channels.output.find("rain.A"), std::string::npos) << channels.output;
  EXPECT_NE(channels.output.find("depth.Z"), std::string::npos) << channels.output;
  EXPECT_NE(channels.output.find("pluvia:presetHash"), std::string::npos) << channels.output;
  // An AOV named twice is written once, not as a second set of unnamed channels.
  auto twice = (dir / "twice.####.exr").string();
  r = runPluvia({"render", exampleClip().string(), "-p", "moderate", "-o", twice, "--frames", "3-3",
                 "--aov", "rain,rain", "--proxy", "0.5"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  channels = runProcess({"oiiotool", "--info", "-v", (dir / "twice.0003.exr").string()});
  EXPECT_NE(channels.output.find("rain.A"), std::string::npos) << channels.output;
  EXPECT_EQ(channels.output.find("channel8"), std::string::npos) << channels.output;
}

// Without a rain or matte AOV the rain layer's planes are scratch handed from frame to frame (not
// made and zeroed anew): the beauty is the same as a render that writes them out, every frame.
TEST(CliRender, TheBeautyIsTheSameWhetherTheRainLayerIsWrittenOrNot) {
  auto dir = freshTempDir("render_rain_scratch");
  for (const char* name : {"plain", "aov"}) {
    std::vector<std::string> args = {
        "render",   exampleClip().string(),
        "-p",       "storm",
        "--proxy",  "0.5",
        "--frames", "0-3",
        "-o",       (dir / (std::string(name) + ".####.exr")).string()};
    if (std::string(name) == "aov") args.insert(args.end(), {"--aov", "rain,matte"});
    const auto r = runPluvia(args);
    ASSERT_EQ(r.exitCode, 0) << r.output;
  }
  for (int frame = 0; frame <= 3; ++frame) {
    const std::string suffix = ".000" + std::to_string(frame) + ".exr";
    const Image plain = readImageFile(dir / ("plain" + suffix));
    const Image aov = readImageFile(dir / ("aov" + suffix));
    ASSERT_EQ(plain.rgba.size(), aov.rgba.size());
    EXPECT_EQ(plain.rgba, aov.rgba) << "frame " << frame;
  }
}
