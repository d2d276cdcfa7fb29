// The day-time stages with a moving camera: splashes (with their splatters), the rainbow and
// the skylight fog render the same frames, every channel byte for byte (the splash AOV
// included), in two chunks as in one run, the second chunk starting cold (no splash kept from
// the frames before it); and at the extremes (sun at the horizon and at the zenith, 0.1 and
// 500 mm/h, no ground in view) every sample is finite.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

// A day: a wide lens 1.6 m over the ground (depth by layers), a sun behind the camera 30 deg
// up, heavy rain with splashes and splatters on the ground within 5.8 m (min_size_px 0.1 at this
// small frame's focal length), skylight fog; the camera walks forward and turns.
std::vector<std::string> dayArgs() {
  const std::vector<std::string> sets{
      "rain.rate_mm_h=100",
      "rain.seed=3",
      "camera.fov_deg=90",
      "camera.tilt_deg=10",
      "camera.exposure_s=0.02",
      R"(camera.path=[{"frame":1,"position_m":[0,1.6,0],"pitch_deg":-10},{"frame":4,"position_m":[0.5,1.7,-2],"yaw_deg":15,"pitch_deg":-12}])",
      R"(depth.layers=[{"type":"ground"}])",
      "depth.source=layers",
      "splash.min_size_px=0.1",
      "lights.enabled=false",
      "splash.splatter=true",
      "fog.model=skylight",
      "fog.density=0.01",
      "rainbow.sun=direction",
      "rainbow.sun_elevation_deg=30",
      "rainbow.sun_azimuth_deg=180",
      "rainbow.strength=5"};
  std::vector<std::string> args{"-p", "moderate"};
  for (const std::string& s : sets) args.insert(args.end(), {"--set", s});
  return args;
}

CommandResult render(const std::string& plate, const stdfs::path& out, const std::string& frames,
                     std::vector<std::string> extra = {}) {
  std::vector<std::string> args{"render",   plate,  "-o",    out.string(),
                                "--frames", frames, "--aov", "splash"};
  const std::vector<std::string> day = dayArgs();
  args.insert(args.end(), day.begin(), day.end());
  args.insert(args.end(), extra.begin(), extra.end());
  return runPluvia(args);
}

std::string frameFile(const std::string& stem, int frame) {
  return stem + ".000" + std::to_string(frame) + ".exr";
}

}  // namespace

TEST(CliDayChunks, MovingCameraTwoChunksGiveTheOneRunFramesByteForByte) {
  const auto dir = freshTempDir("day_chunks");
  const std::string plate = writeTexturedPlate(dir, 1, 4, 96, 64);
  auto one = render(plate, dir / "one.####.exr", "1-4");
  ASSERT_EQ(one.exitCode, 0) << one.output;
  for (const char* frames : {"1-2", "3-4"}) {
    auto chunk = render(plate, dir / "chunk.####.exr", frames);
    ASSERT_EQ(chunk.exitCode, 0) << chunk.output;
  }
  for (int f = 1; f <= 4; ++f) {
    const ExrPixels a = readAllChannels(dir / frameFile("one", f));
    const ExrPixels b = readAllChannels(dir / frameFile("chunk", f));
    ASSERT_EQ(a.channels, b.channels);
    EXPECT_EQ(a.samples, b.samples) << "frame " << f;
  }
  // The comparison means something: splashes at the chunk boundary, and the rainbow and the
  // skylight fog change the frame there.
  const ExrPixels boundary = readAllChannels(dir / frameFile("chunk", 3));
  EXPECT_GT(channelSum(boundary, "splash.A"), 1.0);
  auto plain = render(plate, dir / "plain.####.exr", "3-3",
                      {"--set", "rainbow.enabled=false", "--set", "fog.model=exponential"});
  ASSERT_EQ(plain.exitCode, 0) << plain.output;
  const ExrPixels without = readAllChannels(dir / frameFile("plain", 3));
  ASSERT_EQ(without.samples.size(), boundary.samples.size());
  double difference = 0.0;
  for (size_t i = 0; i < without.samples.size(); ++i)
    difference += std::abs(without.samples[i] - boundary.samples[i]);
  EXPECT_GT(difference / double(without.samples.size()), 1e-3);
}

TEST(CliDayChunks, FiniteAtTheExtremes) {
  const auto dir = freshTempDir("day_extremes");
  const std::string plate = writeTexturedPlate(dir, 1, 1, 48, 32);
  struct Case {
    const char* name;
    std::vector<std::string> sets;
  };
  const std::vector<Case> cases = {
      {"horizon_drizzle", {"rainbow.sun_elevation_deg=0.01", "rain.rate_mm_h=0.1"}},
      {"zenith_downpour", {"rainbow.sun_elevation_deg=90", "rain.rate_mm_h=500"}},
      // Looking up: no ground in view, nothing takes a splash.
      {"no_ground",
       {"rain.rate_mm_h=500",
        R"(camera.path=[{"frame":1,"position_m":[0,1.6,0],"pitch_deg":60}])"}},
  };
  for (const Case& c : cases) {
    std::vector<std::string> extra;
    for (const std::string& s : c.sets) extra.insert(extra.end(), {"--set", s});
    auto r = render(plate, dir / (std::string(c.name) + ".####.exr"), "1-1", extra);
    ASSERT_EQ(r.exitCode, 0) << c.name << ": " << r.output;
    const ExrPixels p = readAllChannels(dir / frameFile(c.name, 1));
    ASSERT_FALSE(p.samples.empty());
    for (float v : p.samples) ASSERT_TRUE(std::isfinite(v)) << c.name;
    if (std::string(c.name) == "no_ground") {
      EXPECT_EQ(channelSum(p, "splash.A"), 0.0);
    }
  }
}
