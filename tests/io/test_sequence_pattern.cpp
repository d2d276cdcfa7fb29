#include "io/sequence_pattern.h"

#include <fstream>

#include <gtest/gtest.h>

#include "test_support.h"

namespace pluvia {
namespace {

void touch(const std::filesystem::path& path) {
  std::ofstream(path) << "x";
}

TEST(SequencePattern, ParsesHashes) {
  auto pattern = SequencePattern::parse("shots/plate.####.exr");
  ASSERT_TRUE(pattern);
  EXPECT_EQ(pattern->prefix, "shots/plate.");
  EXPECT_EQ(pattern->suffix, ".exr");
  EXPECT_EQ(pattern->padding, 4);
  EXPECT_EQ(pattern->pathFor(7), "shots/plate.0007.exr");
  EXPECT_EQ(pattern->pathFor(1001), "shots/plate.1001.exr");
  EXPECT_EQ(pattern->pathFor(12345), "shots/plate.12345.exr");
}

TEST(SequencePattern, ParsesPrintfTokens) {
  auto padded = SequencePattern::parse("out_%05d.png");
  ASSERT_TRUE(padded);
  EXPECT_EQ(padded->prefix, "out_");
  EXPECT_EQ(padded->suffix, ".png");
  EXPECT_EQ(padded->padding, 5);
  EXPECT_EQ(padded->pathFor(42), "out_00042.png");

  auto plain = SequencePattern::parse("f%d.jpg");
  ASSERT_TRUE(plain);
  EXPECT_EQ(plain->padding, 0);
  EXPECT_EQ(plain->pathFor(0), "f0.jpg");
  EXPECT_EQ(plain->pathFor(1001), "f1001.jpg");
}

TEST(SequencePattern, SingleHashAndTokenAtTheEdges) {
  auto single = SequencePattern::parse("#.tif");
  ASSERT_TRUE(single);
  EXPECT_EQ(single->prefix, "");
  EXPECT_EQ(single->padding, 1);
  EXPECT_EQ(single->pathFor(3), "3.tif");
  EXPECT_EQ(single->pathFor(10), "10.tif");
}

TEST(SequencePattern, AtSignsAreOneDigitEach) {
  auto pattern = SequencePattern::parse("shots/plate.@@@@.exr");
  ASSERT_TRUE(pattern);
  EXPECT_EQ(pattern->prefix, "shots/plate.");
  EXPECT_EQ(pattern->suffix, ".exr");
  EXPECT_EQ(pattern->padding, 4);
  EXPECT_EQ(pattern->pathFor(7), "shots/plate.0007.exr");
  auto single = SequencePattern::parse("f.@.png");
  ASSERT_TRUE(single);
  EXPECT_EQ(single->padding, 1);
  EXPECT_EQ(single->pathFor(12), "f.12.png");
  // The last token wins, whichever kind: '@' in a folder name, '#' in the file name.
  auto mixed = SequencePattern::parse("take@2/plate.###.png");
  ASSERT_TRUE(mixed);
  EXPECT_EQ(mixed->prefix, "take@2/plate.");
  EXPECT_EQ(mixed->padding, 3);
}

TEST(SequencePattern, AtPatternFindsTheSameFramesAsHashes) {
  auto dir = test::freshTempDir("sequence_pattern_at");
  for (const char* name : {"p.1001.exr", "p.1003.exr", "p.101.exr"}) touch(dir / name);
  auto at = SequencePattern::parse((dir / "p.@@@@.exr").string());
  auto hash = SequencePattern::parse((dir / "p.####.exr").string());
  ASSERT_TRUE(at && hash);
  EXPECT_EQ(at->existingFrames(), (std::vector<int64_t>{1001, 1003}));
  EXPECT_EQ(at->existingFrames(), hash->existingFrames());
}

TEST(SequencePattern, RejectsStringsWithoutAFrameToken) {
  EXPECT_FALSE(SequencePattern::parse("plate.exr"));
  EXPECT_FALSE(SequencePattern::parse("movie.mp4"));
  EXPECT_FALSE(SequencePattern::parse("100%.png"));
  EXPECT_FALSE(SequencePattern::parse("a%4d.png"));  // space padding is not a frame token
  EXPECT_FALSE(SequencePattern::parse("a%s.png"));
  EXPECT_FALSE(SequencePattern::parse(""));
}

TEST(SequencePattern, TheLastTokenIsTheFrameNumber) {
  auto pattern = SequencePattern::parse("take#2/plate.%03d.png");
  ASSERT_TRUE(pattern);
  EXPECT_EQ(pattern->prefix, "take#2/plate.");
  EXPECT_EQ(pattern->padding, 3);
}

TEST(SequencePattern, FindsExistingFramesWithGaps) {
  auto dir = test::freshTempDir("sequence_pattern_gaps");
  for (const char* name : {"plate.1001.exr", "plate.1002.exr", "plate.1005.exr", "plate.10000.exr"})
    touch(dir / name);
  // Not frames of the pattern: too few digits, extra zero, other suffix or prefix, not digits.
  for (const char* name : {"plate.101.exr", "plate.01002.exr", "plate.1003.png", "plates.1004.exr",
                           "plate.10a4.exr", "plate..exr", "plate.1006.exr.tmp"}) {
    touch(dir / name);
  }
  std::filesystem::create_directory(dir / "plate.1007.exr");  // a folder is not a frame
  auto pattern = SequencePattern::parse((dir / "plate.####.exr").string());
  ASSERT_TRUE(pattern);
  EXPECT_EQ(pattern->existingFrames(), (std::vector<int64_t>{1001, 1002, 1005, 10000}));
}

TEST(SequencePattern, UnpaddedPatternMatchesAnyDigitCountWithoutLeadingZeros) {
  auto dir = test::freshTempDir("sequence_pattern_unpadded");
  for (const char* name : {"f1.png", "f2.png", "f10.png", "f010.png"}) touch(dir / name);
  auto pattern = SequencePattern::parse((dir / "f%d.png").string());
  ASSERT_TRUE(pattern);
  EXPECT_EQ(pattern->existingFrames(), (std::vector<int64_t>{1, 2, 10}));
}

TEST(SequencePattern, PatternInAFolderOfItsOwn) {
  auto dir = test::freshTempDir("sequence_pattern_folder");
  touch(dir / "00001.jpg");
  touch(dir / "00002.jpg");
  auto pattern = SequencePattern::parse((dir / "%05d.jpg").string());
  ASSERT_TRUE(pattern);
  EXPECT_EQ(pattern->existingFrames(), (std::vector<int64_t>{1, 2}));
}

TEST(SequencePattern, MissingFolderHasNoFrames) {
  auto pattern = SequencePattern::parse("/nonexistent-pluvia-folder/plate.####.exr");
  ASSERT_TRUE(pattern);
  EXPECT_TRUE(pattern->existingFrames().empty());
}

TEST(SequencePattern, Extensions) {
  EXPECT_EQ(lowerExtension("a/b/Plate.0001.EXR"), "exr");
  EXPECT_EQ(lowerExtension("noext"), "");
  EXPECT_EQ(lowerExtension("dir.d/noext"), "");
  for (const char* movie : {"a.mp4", "b.MOV", "c.avi", "d.mkv", "e.m4v", "f.webm"})
    EXPECT_TRUE(isMovieExtension(movie)) << movie;
  for (const char* other : {"a.exr", "b.png", "c.mp4.png", "mp4", "d.mpeg4"})
    EXPECT_FALSE(isMovieExtension(other)) << other;
}

}  // namespace
}  // namespace pluvia
