// --cache keeps the per-clip results made from the frames (the still, the sky found in it,
// whether the plate was shot in rain) and the drop's radiance map, each under a key of only
// what it depends on: a look change (rate, wind, opacity, exposure) finds them all and redoes
// none of that work, a change of where the camera looks (its tilt) makes the sky and the
// lighting again but keeps the still, and a frame made from the cache is the frame made without.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "test_support.h"
#include "util/fs.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

int entriesStartingWith(const stdfs::path& folder, const std::string& prefix,
                        const std::string& extension) {
  int n = 0;
  for (const auto& entry : stdfs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) == 0 && entry.path().extension() == extension) ++n;
  }
  return n;
}

// The line of `output` that holds `what` ("" when none).
std::string lineWith(const std::string& output, const std::string& what) {
  const size_t at = output.find(what);
  if (at == std::string::npos) return "";
  const size_t start = output.rfind('\n', at) + 1;  // npos + 1 = 0
  return output.substr(start, output.find('\n', at) - start);
}

bool plateRainFromCache(const std::string& output) {
  return lineWith(output, "plate: not shot in rain").ends_with("from cache");
}

struct Rendered {
  CommandResult result;
  std::string frame;  // the written frame's bytes
};

}  // namespace

TEST(CliClipCache, ALookChangeRedoesNoneOfThePerClipWorkAndTheFrameIsTheSame) {
  const stdfs::path dir = freshTempDir("clip_cache");
  const std::string input = writeTexturedPlate(dir, 1, 8, 96, 64);
  const stdfs::path cache = dir / "cache";
  int runs = 0;
  auto render = [&](const std::vector<std::string>& sets) {
    const stdfs::path out = dir / ("out" + std::to_string(++runs) + ".####.exr");
    std::vector<std::string> args = {"render",   input,          "-p", "moderate",
                                     "--cache",  cache.string(), "-o", out.string(),
                                     "--frames", "4-4",          "-v"};
    for (const std::string& set : sets) args.insert(args.end(), {"--set", set});
    Rendered run{runPluvia(args), ""};
    EXPECT_EQ(run.result.exitCode, 0) << run.result.output;
    const stdfs::path written = dir / ("out" + std::to_string(runs) + ".0004.exr");
    if (stdfs::exists(written)) run.frame = fs::readTextFile(written);
    return run;
  };
  const std::vector<std::string> fromCache = {"still: the median of the clip's frames, from cache",
                                              "sky: found in the still, from cache", ", from cache",
                                              "lighting: from the plate, from cache"};

  // `plan` says what the render will find in the cache: nothing before the first render.
  auto plan = [&] {
    return runPluvia({"plan", input, "-p", "moderate", "--cache", cache.string()});
  };
  const CommandResult planBefore = plan();
  ASSERT_EQ(planBefore.exitCode, 0) << planBefore.output;
  EXPECT_EQ(planBefore.output.find("from the cache"), std::string::npos) << planBefore.output;

  const Rendered cold = render({});
  const CommandResult planAfter = plan();
  expectOutputHas(planAfter.output,
                  {"the still from the cache", "the plate's rain check from the cache"});
  for (const std::string& line : fromCache)
    EXPECT_EQ(cold.result.output.find(line), std::string::npos) << line << " in a cold run";
  EXPECT_NE(cold.result.output.find("still: the median of 5 frames in"), std::string::npos)
      << cold.result.output;
  ASSERT_NE(lineWith(cold.result.output, "plate: not shot in rain"), "") << cold.result.output;
  EXPECT_FALSE(plateRainFromCache(cold.result.output));
  EXPECT_EQ(entriesStartingWith(cache, "still-", ".bin"), 1);
  EXPECT_EQ(entriesStartingWith(cache, "sky-", ".bin"), 1);
  EXPECT_EQ(entriesStartingWith(cache, "plate-rain-", ".json"), 1);
  EXPECT_EQ(entriesStartingWith(cache, "drop-radiance-", ".bin"), 2);  // the rain's and splash's

  // The same look again: every per-clip result from the cache, the same frame.
  const Rendered warm = render({});
  expectOutputHas(warm.result.output, fromCache);
  expectOutputHas(warm.result.output, {"drop radiance map", "from cache"});
  EXPECT_TRUE(plateRainFromCache(warm.result.output)) << warm.result.output;
  EXPECT_EQ(warm.result.output.find("still: the median of 5 frames in"), std::string::npos);
  ASSERT_FALSE(cold.frame.empty());
  EXPECT_EQ(warm.frame, cold.frame) << "a frame made from the cache differs";

  // A look change: nothing per clip is made again, nothing new is stored.
  const Rendered look =
      render({"rain.rate_mm_h=20", "rain.wind.speed_m_s=4", "camera.exposure_s=0.004"});
  expectOutputHas(look.result.output, fromCache);
  EXPECT_TRUE(plateRainFromCache(look.result.output)) << look.result.output;
  EXPECT_EQ(look.result.output.find("still: the median of 5 frames in"), std::string::npos);
  EXPECT_NE(look.frame, cold.frame) << "the look change changed nothing";
  EXPECT_EQ(entriesStartingWith(cache, "sky-", ".bin"), 1);
  EXPECT_EQ(entriesStartingWith(cache, "lighting-", ".json"), 1);

  // Where the camera looks: the sky (its horizon) and the lighting are made again, the still
  // and the plate's rain are not.
  const Rendered tilted = render({"camera.tilt_deg=8"});
  expectOutputHas(tilted.result.output, {"still: the median of the clip's frames, from cache"});
  EXPECT_TRUE(plateRainFromCache(tilted.result.output)) << tilted.result.output;
  EXPECT_EQ(tilted.result.output.find("sky: found in the still, from cache"), std::string::npos);
  EXPECT_EQ(tilted.result.output.find("lighting: from the plate, from cache"), std::string::npos);
  EXPECT_EQ(entriesStartingWith(cache, "sky-", ".bin"), 2);
  EXPECT_EQ(entriesStartingWith(cache, "still-", ".bin"), 1);
}

// A movie's frame count, which opening it checks by decoding from the last frame its container
// lists, is kept in the cache under the file's identity: a second process (a farm's chunk after
// `prepare`) takes it from there and decodes nothing to count; an entry that is not a count, or
// is shorter than the container's own, is ignored with a warning, counted again and replaced.
TEST(CliClipCache, AMovieFrameCountComesFromTheCacheInTheNextProcess) {
  const stdfs::path dir = freshTempDir("clip_cache_movie_frames");
  const std::string movie = (dir / "plate.mp4").string();
  ASSERT_EQ(runProcess({"ffmpeg", "-v", "error", "-f", "lavfi", "-i", "testsrc=size=96x64:rate=24",
                        "-frames:v", "24", "-c:v", "libx264", "-pix_fmt", "yuv420p", movie})
                .exitCode,
            0);
  const stdfs::path cache = dir / "cache";
  int runs = 0;
  auto render = [&] {
    const stdfs::path out = dir / ("out" + std::to_string(++runs) + ".####.png");
    return runPluvia({"render", movie, "-p", "drizzle", "--cache", cache.string(), "-o",
                      out.string(), "--frames", "3-3", "-v"});
  };
  const CommandResult cold = render();
  ASSERT_EQ(cold.exitCode, 0) << cold.output;
  EXPECT_EQ(lineWith(cold.output, "plate.mp4: 24 frames, from cache"), "");
  ASSERT_EQ(entriesStartingWith(cache, "movie-frames-", ".json"), 1);
  stdfs::path entry;
  for (const auto& file : stdfs::directory_iterator(cache))
    if (file.path().filename().string().rfind("movie-frames-", 0) == 0) entry = file.path();
  EXPECT_NE(fs::readTextFile(entry).find("\"frames\": 24"), std::string::npos)
      << fs::readTextFile(entry);

  const CommandResult warm = render();
  ASSERT_EQ(warm.exitCode, 0) << warm.output;
  EXPECT_NE(lineWith(warm.output, "plate.mp4: 24 frames, from cache"), "") << warm.output;

  // Not a count, and a count shorter than the container's: each is not taken, the movie is
  // counted again (the frame rendered) and the count replaces the entry for the next process.
  for (const std::string& edit : {"{\"frames\": \"many\"}", "{\"frames\": 5}"}) {
    fs::writeTextFile(entry, edit);
    const CommandResult edited = render();
    ASSERT_EQ(edited.exitCode, 0) << edited.output;
    EXPECT_NE(lineWith(edited.output, "not the movie's frame count (24)"), "") << edit;
    EXPECT_EQ(lineWith(edited.output, "plate.mp4: 24 frames, from cache"), "") << edit;
    EXPECT_TRUE(stdfs::exists(dir / fmt::format("out{}.0003.png", runs))) << edit;
    const CommandResult mended = render();
    EXPECT_NE(lineWith(mended.output, "plate.mp4: 24 frames, from cache"), "") << edit;
  }
}
