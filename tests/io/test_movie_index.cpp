// io/movie_index.h: a QuickTime-family movie is whole only with its 'moov' box and boxes that end
// at the end of the file. ffmpeg 5 exits 0 when the disk fills as it writes the index; these are
// the files it then leaves.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io/movie_index.h"
#include "test_support.h"
#include "util/fs.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

std::string box(const std::string& type, size_t payload) {
  std::string bytes(8 + payload, '\0');
  const uint32_t size = uint32_t(8 + payload);
  for (int i = 0; i < 4; ++i) bytes[size_t(i)] = char(size >> (24 - 8 * i));
  bytes.replace(4, 4, type);
  return bytes;
}

stdfs::path write(const stdfs::path& dir, const std::string& name, const std::string& bytes) {
  std::ofstream(dir / name, std::ios::binary) << bytes;
  return dir / name;
}

}  // namespace

TEST(MovieIndex, BoxesEndingAtTheEndWithAMoovAreWhole) {
  const stdfs::path dir = freshTempDir("movie_index_boxes");
  const std::string ftyp = box("ftyp", 16), mdat = box("mdat", 1000), moov = box("moov", 200);
  EXPECT_EQ(movieIndexProblem(write(dir, "whole.mp4", ftyp + mdat + moov).string()), "");
  EXPECT_EQ(movieIndexProblem(write(dir, "faststart.mov", ftyp + moov + mdat).string()), "");
  // What a full disk leaves: the media data, no index.
  EXPECT_NE(movieIndexProblem(write(dir, "full.mp4", ftyp + box("free", 0) + mdat).string())
                .find("no index ('moov' box)"),
            std::string::npos);
  // The index cut short, and a box header cut short.
  const std::string cut = ftyp + mdat + moov.substr(0, 100);
  EXPECT_NE(movieIndexProblem(write(dir, "cut.mp4", cut).string()).find("'moov' box runs past"),
            std::string::npos);
  EXPECT_NE(movieIndexProblem(write(dir, "header.m4v", ftyp + mdat + moov + "abc").string())
                .find("inside a box header"),
            std::string::npos);
  // A 64-bit size (size 1) and a last box to the end of the file (size 0).
  std::string large = box("mdat", 0);
  large.replace(0, 4, std::string("\0\0\0\1", 4));
  large += std::string("\0\0\0\0\0\0\0\x18", 8) + std::string(8, 'x');
  std::string toEnd = box("moov", 0);
  toEnd.replace(0, 4, std::string(4, '\0'));
  EXPECT_EQ(movieIndexProblem(write(dir, "large.mp4", ftyp + large + toEnd + "xyz").string()), "");
  // Other containers are not of that family: unchecked.
  EXPECT_EQ(movieIndexProblem(write(dir, "m.mkv", "not a box").string()), "");
}

TEST(MovieIndex, AMovieFfmpegFinishedIsWholeAndCutShortIsNot) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  const stdfs::path dir = freshTempDir("movie_index_ffmpeg");
  const stdfs::path movie = dir / "m.mp4";
  const ProcessResult r =
      runProcess({"ffmpeg", "-v", "error", "-f", "lavfi", "-i", "testsrc=size=64x48:rate=24",
                  "-frames:v", "6", "-c:v", "libx264", "-pix_fmt", "yuv420p", movie.string()});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(movieIndexProblem(movie.string()), "");
  const std::string bytes = fs::readTextFile(movie);
  EXPECT_NE(movieIndexProblem(write(dir, "cut.mp4", bytes.substr(0, bytes.size() - 10)).string()),
            "");
}
