// A movie pluvia leaves is whole and the size it says (adversarial pass, issue 59): an H.264
// movie whose index the full disk cut off used to be committed with exit 0, and --skip-existing
// kept a proxy's movie as the final.
#include <gtest/gtest.h>
#include <sys/mount.h>

#include <filesystem>

#include "io/clip_reader.h"
#include "test_support.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

TEST(CliWholeMovies, AMovieTheFullDiskCutShortFailsAndIsNotLeft) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  const stdfs::path dir = freshTempDir("whole_movie_full");
  const std::string plate = writeTexturedPlate(dir, 1, 12, 320, 240);
  const stdfs::path full = dir / "full";
  stdfs::create_directories(full);
  // 48 KB: the media data fits, the index after it does not (needs root: skipped otherwise).
  if (::mount("tmpfs", full.c_str(), "tmpfs", 0, "size=48k") != 0)
    GTEST_SKIP() << "cannot mount a small tmpfs here (not root)";
  const auto r = runPluvia({"render", plate, "-p", "drizzle", "-o", (full / "r.mp4").string()});
  std::vector<std::string> left;
  for (const auto& entry : stdfs::directory_iterator(full)) left.push_back(entry.path().string());
  ::umount(full.c_str());
  EXPECT_EQ(r.exitCode, 1) << r.output;
  expectOutputHas(r.output, {"r.mp4", "error:"});
  EXPECT_TRUE(left.empty()) << left.front();
}

TEST(CliWholeMovies, SkipExistingRendersAProxysMovieAgainAtFullSize) {
  if (!programAvailable("ffmpeg")) GTEST_SKIP() << "ffmpeg not on PATH";
  const stdfs::path dir = freshTempDir("whole_movie_proxy");
  const std::string plate = writeTexturedPlate(dir, 1, 3, 128, 96);
  const std::string movie = (dir / "r.mp4").string();
  ASSERT_EQ(runPluvia({"render", plate, "-p", "drizzle", "--proxy", "0.5", "-o", movie}).exitCode,
            0);
  const auto r = runPluvia({"render", plate, "-p", "drizzle", "-o", movie, "--skip-existing"});
  ASSERT_EQ(r.exitCode, 0) << r.output;
  expectOutputHas(r.output,
                  {"rendering " + movie + " again: it is 64x48, this render makes 128x96"});
  EXPECT_EQ(openClip(movie)->info().width, 128);
  const auto again = runPluvia({"render", plate, "-p", "drizzle", "-o", movie, "--skip-existing"});
  expectOutputHas(again.output, {"exists, nothing to do"});
}
