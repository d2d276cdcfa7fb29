#include "io/frame_list.h"

#include <algorithm>

#include <OpenImageIO/filesystem.h>
#include <gtest/gtest.h>

#include "util/error.h"

namespace pluvia {
namespace {

using Frames = std::vector<int64_t>;

TEST(FrameList, RangesStepsAndCommas) {
  EXPECT_EQ(parseFrameList("12"), Frames{12});
  EXPECT_EQ(parseFrameList("1001-1004"), (Frames{1001, 1002, 1003, 1004}));
  EXPECT_EQ(parseFrameList("1001-1010x3"), (Frames{1001, 1004, 1007, 1010}));
  EXPECT_EQ(parseFrameList("1001-1011x3"), (Frames{1001, 1004, 1007, 1010}));  // 1011 not hit
  EXPECT_EQ(parseFrameList("5,1-3,3"), (Frames{1, 2, 3, 5}));                  // sorted, each once
  EXPECT_EQ(parseFrameList("-2-1"), (Frames{-2, -1, 0, 1}));
  const Frames stepped = parseFrameList("1001-1100x2");
  ASSERT_EQ(stepped.size(), 50u);
  EXPECT_EQ(stepped.front(), 1001);
  EXPECT_EQ(stepped.back(), 1099);
}

// OpenImageIO's own parser of the same syntax is the independent reference.
TEST(FrameList, AgreesWithOpenImageIO) {
  for (const char* text : {"1001-1100x2", "1-10", "3,7,20-30x5", "1001-1100x7,1200", "42"}) {
    std::vector<int> reference;
    ASSERT_TRUE(OIIO::Filesystem::enumerate_sequence(text, reference)) << text;
    Frames expected(reference.begin(), reference.end());
    std::sort(expected.begin(), expected.end());
    expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
    EXPECT_EQ(parseFrameList(text), expected) << text;
  }
}

TEST(FrameList, BadItemsAreUsageErrorsNamingTheItem) {
  for (const char* text : {"ten", "1-", "5-1", "1-10x0", "1-10x-2", "1x2", "1,,2", "", "1-10y2"}) {
    try {
      parseFrameList(text);
      ADD_FAILURE() << "no error for '" << text << "'";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("'") + text + "'"), std::string::npos)
          << e.what();
    }
  }
  EXPECT_THROW(parseFrameList("0-100000000"), UsageError);  // over the frame limit
  EXPECT_THROW(parseFrameList("0-20", 10), UsageError);
}

TEST(FrameList, Contiguity) {
  EXPECT_TRUE(isContiguous({4, 5, 6}));
  EXPECT_TRUE(isContiguous({9}));
  EXPECT_FALSE(isContiguous({1, 3}));
}

}  // namespace
}  // namespace pluvia
