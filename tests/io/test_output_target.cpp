#include "io/output_target.h"

#include <gtest/gtest.h>

#include "util/error.h"

namespace pluvia {
namespace {

TEST(OutputTarget, TellsAMovieASequenceAndOneImage) {
  const OutputTarget movie = OutputTarget::classify("out/rain.MOV");
  EXPECT_TRUE(movie.isMovie());
  EXPECT_FALSE(movie.pattern);
  EXPECT_EQ(movie.pathFor(7), "out/rain.MOV");

  const OutputTarget sequence = OutputTarget::classify("out/rain.%04d.exr");
  EXPECT_TRUE(sequence.isSequence());
  ASSERT_TRUE(sequence.pattern);
  EXPECT_EQ(sequence.pattern->prefix, "out/rain.");
  EXPECT_EQ(sequence.pathFor(7), "out/rain.0007.exr");

  const OutputTarget still = OutputTarget::classify("still.png");
  EXPECT_EQ(still.kind, OutputTarget::Kind::SingleImage);
  EXPECT_EQ(still.pathFor(7), "still.png");
  EXPECT_EQ(OutputTarget().kind, OutputTarget::Kind::SingleImage);
}

// A movie's extension decides, as it does for an input: the name is the one file written.
TEST(OutputTarget, AMovieNameWithAFrameTokenIsAMovie) {
  const OutputTarget movie = OutputTarget::classify("rain.####.mp4");
  EXPECT_TRUE(movie.isMovie());
  EXPECT_EQ(movie.pathFor(3), "rain.####.mp4");
}

TEST(OutputTarget, RefusesAPaddingBeyondNineteenDigits) {
  EXPECT_THROW(OutputTarget::classify("rain.%020d.exr"), Error);
}

}  // namespace
}  // namespace pluvia
