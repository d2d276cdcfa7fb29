// End-to-end: `--start-frame` numbers a movie's frames as the facility numbers its plate (issue
// 30): a movie numbered from 1001 renders, names and rains its frames exactly as the same
// pictures as a sequence numbered from 1001 do.
#include <gtest/gtest.h>

#include <filesystem>

#include <fmt/format.h>

#include "test_support.h"
#include "util/fs.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

// The plate's frames 0..3 as a lossless movie (PNG in MOV, 24 fps as a sequence is read) and as
// a sequence of the same pictures numbered 1001..1004.
struct TwoPlates {
  std::string movie, sequence;
};

TwoPlates writeTwoPlates(const stdfs::path& dir) {
  stdfs::create_directories(dir / "frames");
  writeTexturedPlate(dir / "frames", 0, 3, 96, 64);
  stdfs::create_directories(dir / "seq");
  for (int i = 0; i < 4; ++i)
    stdfs::copy_file(dir / "frames" / fmt::format("plate.{:04d}.png", i),
                     dir / "seq" / fmt::format("plate.{:04d}.png", 1001 + i));
  const std::string movie = (dir / "plate.mov").string();
  const ProcessResult made =
      runProcess({"ffmpeg", "-v", "error", "-y", "-framerate", "24", "-i",
                  (dir / "frames" / "plate.%04d.png").string(), "-c:v", "png", movie});
  EXPECT_EQ(made.exitCode, 0) << made.output;
  return {movie, (dir / "seq" / "plate.####.png").string()};
}

}  // namespace

TEST(CliMovieNumbering, StartFrameRendersTheFramesOfASequenceOfThoseNumbers) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  const stdfs::path dir = freshTempDir("cli_movie_numbering");
  const TwoPlates plates = writeTwoPlates(dir);
  const std::vector<std::string> common{"-p", "moderate", "--frames", "1003", "--aov", "rain"};
  auto args = [&](const std::string& input, const std::string& output) {
    std::vector<std::string> a{"render", input, "-o", (dir / output).string()};
    a.insert(a.end(), common.begin(), common.end());
    return a;
  };
  std::vector<std::string> fromMovie = args(plates.movie, "m.####.exr");
  fromMovie.insert(fromMovie.end(), {"--start-frame", "1001"});
  CommandResult r = runPluvia(fromMovie);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  r = runPluvia(args(plates.sequence, "s.####.exr"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (int frame : {1003}) {
    const ExrPixels movie = readAllChannels(dir / fmt::format("m.{}.exr", frame));
    const ExrPixels sequence = readAllChannels(dir / fmt::format("s.{}.exr", frame));
    ASSERT_EQ(movie.channels, sequence.channels) << frame;
    EXPECT_GT(channelSum(movie, "rain.A"), 0.0) << frame;
    EXPECT_EQ(movie.samples, sequence.samples) << "frame " << frame;
  }
  EXPECT_FALSE(stdfs::exists(dir / "m.0001.exr"));
  EXPECT_FALSE(stdfs::exists(dir / "m.1001.exr"));

  // Unnumbered, the movie's frame 2 is the same picture under another number: other rain.
  r = runPluvia({"render", plates.movie, "-o", (dir / "u.####.exr").string(), "-p", "moderate",
                 "--frames", "2", "--aov", "rain"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(readAllChannels(dir / "u.0002.exr").samples,
            readAllChannels(dir / "m.1003.exr").samples);

  // plan counts the movie's frames from there; a frame before it is not in the clip.
  r = runPluvia({"plan", plates.movie, "-p", "moderate", "--start-frame", "1001"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("4 frames 1001-1004"), std::string::npos) << r.output;
  r = runPluvia({"render", plates.movie, "-o", (dir / "x.####.exr").string(), "-p", "moderate",
                 "--frames", "0-1", "--start-frame", "1001"});
  EXPECT_NE(r.exitCode, 0) << r.output;
  EXPECT_FALSE(stdfs::exists(dir / "x.0000.exr"));
}

TEST(CliMovieNumbering, StartFrameOfASequenceIsAUsageError) {
  const stdfs::path dir = freshTempDir("cli_movie_numbering_sequence");
  const std::string plate = writeTexturedPlate(dir, 1, 2);
  const CommandResult r = runPluvia({"render", plate, "-o", (dir / "o.####.png").string(), "-p",
                                     "moderate", "--start-frame", "1001"});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("is not a movie"), std::string::npos) << r.output;
  EXPECT_FALSE(stdfs::exists(dir / "o.0001.png"));
}

// A farm job numbers the movie as a local render does: its range is checked against the
// renumbered frames and its prepare job and chunks are told the numbering.
TEST(CliMovieNumbering, FarmScriptsCarryTheStartFrame) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  const stdfs::path dir = freshTempDir("cli_movie_numbering_farm");
  const TwoPlates plates = writeTwoPlates(dir);
  CommandResult r = runPluvia({"farm", "slurm", plates.movie, "-p", "moderate", "-o",
                               (dir / "o.####.exr").string(), "--chunk", "2", "--frames",
                               "1001-1004", "--start-frame", "1001"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  for (const char* script : {"prepare.sbatch", "render.sbatch"}) {
    const std::string text = fs::readTextFile(dir / "o.farm" / script);
    EXPECT_NE(text.find("--start-frame 1001"), std::string::npos) << script << "\n" << text;
  }
  r = runPluvia({"farm", "slurm", plates.movie, "-p", "moderate", "-o",
                 (dir / "p.####.exr").string(), "--chunk", "2", "--frames", "0-3", "--start-frame",
                 "1001"});
  EXPECT_EQ(r.exitCode, 2) << r.output;
  EXPECT_NE(r.output.find("frames 1001-1004"), std::string::npos) << r.output;
}
