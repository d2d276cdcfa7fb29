// Video-range Y'CbCr made from float RGB for the movie codecs (io/ycbcr_frame.h),
// against the codes ITU-R BT.709 and BT.2020 give for known colours, worked out by hand.
#include "io/ycbcr_frame.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "test_support.h"
#include "util/error.h"

namespace pluvia {
namespace {

const YcbcrLayout k420{.bits = 8, .chromaColumns = 2, .chromaRows = 2};
const YcbcrLayout k422{.bits = 8, .chromaColumns = 2, .chromaRows = 1};

struct Codes {
  int y, cb, cr;
};

// The codes of a flat 2x2 image, 4:2:0.
Codes codesOf(float r, float g, float b, const char* matrix) {
  std::vector<uint8_t> planes;
  packYcbcr(test::flatImage(2, 2, r, g, b), 2, 2, k420, ycbcrMatrix(matrix, "test.mp4"), planes);
  EXPECT_EQ(planes.size(), 6u);
  for (int i = 1; i < 4; ++i) EXPECT_EQ(planes[i], planes[0]) << "flat luma";
  return {planes[0], planes[4], planes[5]};
}

void expectCodes(const Codes& got, const Codes& want, const char* what) {
  EXPECT_EQ(got.y, want.y) << what;
  EXPECT_EQ(got.cb, want.cb) << what;
  EXPECT_EQ(got.cr, want.cr) << what;
}

TEST(YcbcrFrame, KnownColoursGiveTheStandardsCodes) {
  // Y' = 16 + 219 E'y, C = 128 + 224 E'c: black and white at the ends of video range.
  expectCodes(codesOf(0, 0, 0, "bt709"), {16, 128, 128}, "black");
  expectCodes(codesOf(1, 1, 1, "bt709"), {235, 128, 128}, "white");
  // BT.709 red: E'y = 0.2126 -> 62.56; E'cb = -0.2126 / 1.8556 -> 102.33; E'cr = 0.5 -> 240.
  expectCodes(codesOf(1, 0, 0, "bt709"), {63, 102, 240}, "709 red");
  // BT.709 blue: E'y = 0.0722 -> 31.81; E'cb = 0.5 -> 240; E'cr = -0.0722 / 1.5748 -> 117.73.
  expectCodes(codesOf(0, 0, 1, "bt709"), {32, 240, 118}, "709 blue");
  // The same red by BT.2020: E'y = 0.2627 -> 73.53; E'cb = -0.2627 / 1.8814 -> 96.72.
  expectCodes(codesOf(1, 0, 0, "bt2020nc"), {74, 97, 240}, "2020 red");
  // "" is BT.709 (no tag names a matrix).
  expectCodes(codesOf(1, 0, 0, ""), {63, 102, 240}, "default");
  // Beyond the legal codes (1 to 254) samples clamp to their R'G'B' (238 / 219 and -15 / 219),
  // NaN to 0: E'y = 0.2126 * 1.08676 - 0.7152 * 0.06849 = 0.18205 -> 55.87; E'cb = -0.18205 /
  // 1.8556 -> 106.02; Cr asks for 128 + 224 * 0.90471 / 1.5748 = 256.7 and gets 254.
  expectCodes(codesOf(2.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(), "bt709"),
              {56, 106, 254}, "clamped");
  // Mid grey 0.5: 16 + 109.5 = 125.5 rounds up.
  expectCodes(codesOf(0.5f, 0.5f, 0.5f, "bt709"), {126, 128, 128}, "grey");
}

TEST(YcbcrFrame, ChromaIsTheMeanOfThePixelsItCovers) {
  // Left column white, right column black: luma per pixel, chroma of the pair's mean (grey).
  Image image = test::flatImage(2, 2, 1, 1, 1);
  for (int y = 0; y < 2; ++y) {
    float* p = image.pixel(1, y);
    p[0] = p[1] = p[2] = 0.0f;
  }
  std::vector<uint8_t> planes;
  packYcbcr(image, 2, 2, k420, ycbcrMatrix("bt709", "t.mp4"), planes);
  EXPECT_EQ(planes, (std::vector<uint8_t>{235, 16, 235, 16, 128, 128}));
  // Red over blue, 4:2:0: chroma of (0.5, 0, 0.5): E'y = 0.1424, Cb = 128 + 120.72 * 0.3576
  // = 171.17, Cr = 128 + 142.25 * 0.3576 = 178.87.
  image = test::flatImage(2, 2, 1, 0, 0);
  for (int x = 0; x < 2; ++x) {
    float* p = image.pixel(x, 1);
    p[0] = 0.0f, p[2] = 1.0f;
  }
  packYcbcr(image, 2, 2, k420, ycbcrMatrix("bt709", "t.mp4"), planes);
  EXPECT_EQ(planes, (std::vector<uint8_t>{63, 63, 32, 32, 171, 179}));
  // The same at 4:2:2: a chroma row per luma row, each the colour of its own row.
  packYcbcr(image, 2, 2, k422, ycbcrMatrix("bt709", "t.mp4"), planes);
  EXPECT_EQ(planes, (std::vector<uint8_t>{63, 63, 32, 32, 102, 240, 240, 118}));
}

TEST(YcbcrFrame, OddFramesRepeatTheirLastColumnAndRow) {
  // 3x3, black but for a white last column and a white last row, encoded 4x4.
  Image image = test::flatImage(3, 3, 0, 0, 0);
  for (int i = 0; i < 3; ++i) {
    for (float* p : {image.pixel(2, i), image.pixel(i, 2)}) p[0] = p[1] = p[2] = 1.0f;
  }
  std::vector<uint8_t> planes;
  packYcbcr(image, 4, 4, k420, ycbcrMatrix("bt709", "t.mp4"), planes);
  ASSERT_EQ(planes.size(), 16u + 2u * 4u);
  const std::vector<uint8_t> luma(planes.begin(), planes.begin() + 16);
  EXPECT_EQ(luma, (std::vector<uint8_t>{16, 16, 235, 235,  //
                                        16, 16, 235, 235,  //
                                        235, 235, 235, 235, 235, 235, 235, 235}));
  for (size_t i = 16; i < planes.size(); ++i) EXPECT_EQ(planes[i], 128) << i;
}

TEST(YcbcrFrame, DeepCodecsScaleTheCodesByTwoToTheBitsOverEight) {
  // 12-bit 4:4:4 (ProRes 4444): per pixel chroma, codes (16 + 219 E'y) 16 and (128 + 224 E'c) 16.
  // White 3760 and black 256 exactly (swscale's RGB48 input gave white 3774); BT.709 red:
  // 62.56 * 16 = 1000.9 -> 1001, Cb 102.33 * 16 = 1637.3 -> 1637, Cr 240 * 16 = 3840.
  Image image = test::flatImage(2, 1, 1, 1, 1);
  float* second = image.pixel(1, 0);
  second[0] = 1.0f, second[1] = second[2] = 0.0f;
  std::vector<uint16_t> planes;
  const YcbcrLayout prores4444{.bits = 12, .chromaColumns = 1, .chromaRows = 1};
  packYcbcr(image, 2, 1, prores4444, ycbcrMatrix("bt709", "t.mov"), planes);
  EXPECT_EQ(planes, (std::vector<uint16_t>{3760, 1001, 2048, 1637, 2048, 3840}));
  // 10-bit 4:2:2 (ProRes 422 HQ, DNxHR HQX): white 940, black 64, the pair's chroma its mean.
  image = test::flatImage(2, 1, 1, 1, 1);
  second = image.pixel(1, 0);
  second[0] = second[1] = second[2] = 0.0f;
  const YcbcrLayout tenBit422{.bits = 10, .chromaColumns = 2, .chromaRows = 1};
  packYcbcr(image, 2, 1, tenBit422, ycbcrMatrix("bt709", "t.mov"), planes);
  EXPECT_EQ(planes, (std::vector<uint16_t>{940, 64, 512, 512}));
  // A 16-bit step of the input (1/65535) moves a 12-bit code by 219 * 16 / 65535 = 0.05:
  // mid grey 0.5, 125.5 in 8 bits (halfway between two codes), is 2008.03 at 12.
  packYcbcr(test::flatImage(1, 1, 0.5f, 0.5f, 0.5f), 1, 1, prores4444,
            ycbcrMatrix("bt709", "t.mov"), planes);
  EXPECT_EQ(planes[0], 2008);
}

TEST(YcbcrFrame, SuperWhitesAndSubBlacksKeepTheirLegalCodes) {
  // Grey beyond white and below black (a plate's super-whites and sub-blacks): Y' = 16 + 219 E'
  // until the last legal code, 1 and 254 at 8 bits, 4 and 1019 at 10, 16 and 4079 at 12.
  EXPECT_EQ(codesOf(1.05f, 1.05f, 1.05f, "bt709").y, 246);   // 245.95
  EXPECT_EQ(codesOf(-0.05f, -0.05f, -0.05f, "bt709").y, 5);  // 5.05
  EXPECT_EQ(codesOf(1.2f, 1.2f, 1.2f, "bt709").y, 254);
  EXPECT_EQ(codesOf(-0.2f, -0.2f, -0.2f, "bt709").y, 1);
  std::vector<uint16_t> planes;
  const YcbcrLayout tenBit444{.bits = 10, .chromaColumns = 1, .chromaRows = 1};
  const YcbcrLayout twelveBit444{.bits = 12, .chromaColumns = 1, .chromaRows = 1};
  const auto lumaOf = [&](float grey, const YcbcrLayout& layout) {
    packYcbcr(test::flatImage(1, 1, grey, grey, grey), 1, 1, layout, ycbcrMatrix("bt709", "t.mov"),
              planes);
    return int(planes[0]);
  };
  EXPECT_EQ(lumaOf(1.08f, tenBit444), 1010);  // (16 + 236.52) * 4 = 1010.1
  EXPECT_EQ(lumaOf(-0.06f, tenBit444), 11);   // (16 - 13.14) * 4 = 11.4
  EXPECT_EQ(lumaOf(1.5f, tenBit444), 1019);
  EXPECT_EQ(lumaOf(-0.5f, tenBit444), 4);
  EXPECT_EQ(lumaOf(1.5f, twelveBit444), 4079);
  EXPECT_EQ(lumaOf(-0.5f, twelveBit444), 16);
  // A saturated colour beyond white keeps its chroma legal too: (-0.1, -0.1, 1.5), clamped to
  // (-0.0685, -0.0685, 1.0902), has E'y 0.0152 and asks for Cb (128 + 224 * 1.0750 / 1.8556) * 4
  // = 1031; it gets 1019.
  packYcbcr(test::flatImage(1, 1, -0.1f, -0.1f, 1.5f), 1, 1, tenBit444,
            ycbcrMatrix("bt709", "t.mov"), planes);
  EXPECT_EQ(planes[1], 1019);
}

TEST(YcbcrFrame, UnknownMatrixNamesItAndTheFile) {
  test::expectError([] { ycbcrMatrix("smpte240m", "out/rain.mp4"); }, "smpte240m");
  test::expectError([] { ycbcrMatrix("smpte240m", "out/rain.mp4"); }, "out/rain.mp4");
}

}  // namespace
}  // namespace pluvia
