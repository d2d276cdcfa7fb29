#include "io/sequence_pattern.h"

#include <fstream>

#include <gtest/gtest.h>

#include "test_support.h"

namespace pluvia {
namespace {

void touch(const std::filesystem::path& path) {
  std::ofstream(path) << "x";
}

// The frames that `pattern`, a file name in `dir`, finds once the files `names` are there.
std::vector<int64_t> framesFound(const std::filesystem::path& dir,
                                 const std::vector<std::string>& names,
                                 const std::string& pattern) {
  for (const std::string& name : names) touch(dir / name);
  auto parsed = SequencePattern::parse((dir / pattern).string());
  EXPECT_TRUE(parsed) << pattern;
  return parsed ? parsed->existingFrames() : std::vector<int64_t>{};
}

// A pattern's parts and the paths of some of its frames.
struct ParseCase {
  std::string text, prefix, suffix;
  int padding;
  std::vector<std::pair<int64_t, std::string>> paths;
};

TEST(SequencePattern, ParsesEveryKindOfToken) {
  const std::vector<ParseCase> cases = {
      {"shots/plate.####.exr",
       "shots/plate.",
       ".exr",
       4,
       {{7, "shots/plate.0007.exr"},
        {1001, "shots/plate.1001.exr"},
        {12345, "shots/plate.12345.exr"}}},
      {"out_%05d.png", "out_", ".png", 5, {{42, "out_00042.png"}}},
      {"f%d.jpg", "f", ".jpg", 0, {{0, "f0.jpg"}, {1001, "f1001.jpg"}}},
      // A token at the edge of the name.
      {"#.tif", "", ".tif", 1, {{3, "3.tif"}, {10, "10.tif"}}},
      // '@' is one digit, as '#' is.
      {"shots/plate.@@@@.exr", "shots/plate.", ".exr", 4, {{7, "shots/plate.0007.exr"}}},
      {"f.@.png", "f.", ".png", 1, {{12, "f.12.png"}}},
      // The last token is the frame number, whichever kind: '@' or '#' in a folder name.
      {"take@2/plate.###.png", "take@2/plate.", ".png", 3, {}},
      {"take#2/plate.%03d.png", "take#2/plate.", ".png", 3, {}},
  };
  for (const ParseCase& c : cases) {
    SCOPED_TRACE(c.text);
    auto pattern = SequencePattern::parse(c.text);
    ASSERT_TRUE(pattern);
    EXPECT_EQ(pattern->prefix, c.prefix);
    EXPECT_EQ(pattern->suffix, c.suffix);
    EXPECT_EQ(pattern->padding, c.padding);
    for (const auto& [frame, path] : c.paths) EXPECT_EQ(pattern->pathFor(frame), path);
  }
}

TEST(SequencePattern, AtPatternFindsTheSameFramesAsHashes) {
  auto dir = test::freshTempDir("sequence_pattern_at");
  const std::vector<std::string> names{"p.1001.exr", "p.1003.exr", "p.101.exr"};
  EXPECT_EQ(framesFound(dir, names, "p.@@@@.exr"), (std::vector<int64_t>{1001, 1003}));
  EXPECT_EQ(framesFound(dir, names, "p.####.exr"), (std::vector<int64_t>{1001, 1003}));
}

TEST(SequencePattern, RejectsStringsWithoutAFrameToken) {
  EXPECT_FALSE(SequencePattern::parse("plate.exr"));
  EXPECT_FALSE(SequencePattern::parse("movie.mp4"));
  EXPECT_FALSE(SequencePattern::parse("100%.png"));
  EXPECT_FALSE(SequencePattern::parse("a%4d.png"));  // space padding is not a frame token
  EXPECT_FALSE(SequencePattern::parse("a%s.png"));
  EXPECT_FALSE(SequencePattern::parse(""));
}

TEST(SequencePattern, FindsExistingFramesWithGaps) {
  auto dir = test::freshTempDir("sequence_pattern_gaps");
  std::filesystem::create_directory(dir / "plate.1007.exr");  // a folder is not a frame
  // Besides the frames, files that are not frames of the pattern: too few digits, extra zero,
  // other suffix or prefix, not digits.
  EXPECT_EQ(framesFound(dir,
                        {"plate.1001.exr", "plate.1002.exr", "plate.1005.exr", "plate.10000.exr",
                         "plate.101.exr", "plate.01002.exr", "plate.1003.png", "plates.1004.exr",
                         "plate.10a4.exr", "plate..exr", "plate.1006.exr.tmp"},
                        "plate.####.exr"),
            (std::vector<int64_t>{1001, 1002, 1005, 10000}));
}

TEST(SequencePattern, UnpaddedPatternMatchesAnyDigitCountWithoutLeadingZeros) {
  auto dir = test::freshTempDir("sequence_pattern_unpadded");
  EXPECT_EQ(framesFound(dir, {"f1.png", "f2.png", "f10.png", "f010.png"}, "f%d.png"),
            (std::vector<int64_t>{1, 2, 10}));
}

TEST(SequencePattern, PatternInAFolderOfItsOwn) {
  auto dir = test::freshTempDir("sequence_pattern_folder");
  EXPECT_EQ(framesFound(dir, {"00001.jpg", "00002.jpg"}, "%05d.jpg"), (std::vector<int64_t>{1, 2}));
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
