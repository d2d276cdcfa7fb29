// Timecode arithmetic and the colour tags that output files carry.
#include <gtest/gtest.h>

#include "io/color_tags.h"
#include "io/timecode.h"

namespace pluvia {
namespace {

TEST(Timecode, ParsesCountsOnAndWraps) {
  auto tc = Timecode::parse("01:00:00:00", 24);
  ASSERT_TRUE(tc);
  EXPECT_EQ(tc->frames, 3600 * 24);
  EXPECT_EQ(tc->plus(23).text(), "01:00:00:23");
  EXPECT_EQ(tc->plus(24).text(), "01:00:01:00");
  EXPECT_EQ(tc->plus(-1).text(), "00:59:59:23");
  EXPECT_EQ(Timecode::parse("23:59:59:23", 24)->plus(1).text(), "00:00:00:00");
  // ffprobe writes the frames of a 10 fps timecode with one digit.
  EXPECT_EQ(Timecode::parse("01:00:00:9", 10)->plus(1).text(), "01:00:01:00");
  EXPECT_FALSE(Timecode::parse("01:00:00:24", 24));  // no frame 24 at 24 fps
  EXPECT_FALSE(Timecode::parse("1:00", 24));
  EXPECT_FALSE(Timecode::parse("01:00:00:00x", 24));
}

// SMPTE 12M drop-frame counting at 29.97: labels ;00 and ;01 are skipped at every minute but
// each tenth, so 1 minute of labels holds 1798 frames and 10 minutes 17982.
TEST(Timecode, DropFrameSkipsTheLabelsItShould) {
  auto start = Timecode::parse("00:00:59;29", 29.97);
  ASSERT_TRUE(start);
  EXPECT_TRUE(start->dropFrame);
  EXPECT_EQ(start->plus(1).text(), "00:01:00;02");
  EXPECT_EQ(Timecode::parse("00:09:59;29", 29.97)->plus(1).text(), "00:10:00;00");
  EXPECT_EQ(Timecode::parse("00:10:00;00", 29.97)->frames, 17982);
  EXPECT_EQ(Timecode::parse("00:01:00;02", 29.97)->frames, 1800);
}

TEST(Timecode, SmpteWordsAreBcdAndReadBack) {
  auto tc = Timecode::parse("12:34:56:17", 24);
  ASSERT_TRUE(tc);
  const auto words = tc->smpteWords();
  EXPECT_EQ(words[0], 0x12345617u);
  EXPECT_EQ(words[1], 0u);
  EXPECT_EQ(Timecode::textOfSmpteWord(words[0]), "12:34:56:17");
  EXPECT_EQ(Timecode::textOfSmpteWord(0x01000010u | 0x40u), "01:00:00;10");  // drop-frame bit
}

TEST(ColorTags, KnownSpellingsGetTheirPrimariesAndCurves) {
  const ColorTags srgb = colorTagsFor({"sRGB - Texture"});
  EXPECT_EQ(srgb.name, "sRGB - Texture");
  EXPECT_EQ(srgb.moviePrimaries, "bt709");
  EXPECT_EQ(srgb.movieTransfer, "iec61966-2-1");
  EXPECT_EQ(srgb.movieMatrix, "bt709");
  EXPECT_FALSE(srgb.linear);

  const ColorTags acescg = colorTagsFor({"ACEScg", "lin_ap1"});
  ASSERT_TRUE(acescg.chromaticities);
  EXPECT_FLOAT_EQ((*acescg.chromaticities)[0], 0.713f);
  EXPECT_FLOAT_EQ((*acescg.chromaticities)[6], 0.32168f);
  EXPECT_TRUE(acescg.linear);
  EXPECT_EQ(acescg.moviePrimaries, "");  // no ffmpeg tag for AP1

  const ColorTags linear709 = colorTagsFor({"Linear Rec.709 (sRGB)", "lin_rec709"});
  ASSERT_TRUE(linear709.chromaticities);
  EXPECT_FLOAT_EQ((*linear709.chromaticities)[0], 0.64f);
  EXPECT_TRUE(linear709.linear);
  EXPECT_EQ(linear709.dpxTransfer, "Linear");
  EXPECT_EQ(linear709.dpxColorimetric, "ITU-R 709-4");

  const ColorTags video = colorTagsFor({"rec709"});
  EXPECT_EQ(video.movieTransfer, "bt709");
  EXPECT_EQ(video.dpxTransfer, "ITU-R 709-4");

  const ColorTags wide = colorTagsFor({"lin_rec2020"});
  EXPECT_EQ(wide.moviePrimaries, "bt2020");
  EXPECT_FLOAT_EQ((*wide.chromaticities)[0], 0.708f);

  // An alias can be what is recognised; an unknown space keeps only its name.
  EXPECT_TRUE(colorTagsFor({"Facility Plate Space", "acescg"}).chromaticities);
  const ColorTags unknown = colorTagsFor({"ARRI LogC4"});
  EXPECT_EQ(unknown.name, "ARRI LogC4");
  EXPECT_FALSE(unknown.chromaticities);
  EXPECT_EQ(unknown.moviePrimaries, "");
}

}  // namespace
}  // namespace pluvia
