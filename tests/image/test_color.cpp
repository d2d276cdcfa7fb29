#include "image/color.h"

#include <chrono>
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "test_support.h"
#include "util/error.h"

namespace pluvia {
namespace {

double srgbDecode(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}
double srgbEncode(double v) {
  return v <= 0.0031308 ? v * 12.92 : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
}
double rec709Encode(double v) {
  return v < 0.018 ? v * 4.5 : 1.099 * std::pow(v, 0.45) - 0.099;
}

Image singleRow(const std::vector<float>& values) {
  Image image(static_cast<int>(values.size()), 1);
  for (size_t i = 0; i < values.size(); ++i) {
    for (int c = 0; c < 3; ++c) image.rgba[i * 4 + c] = values[i];
  }
  return image;
}

TEST(Color, SrgbDecodeMatchesTheFormula) {
  Image image = singleRow({0.5f, 0.02f, 1.0f, 0.0f, 0.9f});
  ColorConverter("sRGB", "linear-rec709").apply(image);
  EXPECT_NEAR(image.rgba[0], std::pow((0.5 + 0.055) / 1.055, 2.4), 1e-6);
  EXPECT_NEAR(image.rgba[4], 0.02 / 12.92, 1e-6);  // the linear toe (of a smooth join: within 1e-6)
  EXPECT_NEAR(image.rgba[8], 1.0, 1e-6);
  EXPECT_NEAR(image.rgba[12], 0.0, 1e-6);
  EXPECT_NEAR(image.rgba[16], srgbDecode(0.9), 1e-6);
}

TEST(Color, SrgbEncodeMatchesTheFormula) {
  Image image = singleRow({0.18f, 0.001f, 1.0f});
  ColorConverter("linear-rec709", "sRGB").apply(image);
  EXPECT_NEAR(image.rgba[0], srgbEncode(0.18), 1e-6);
  // OCIO joins the toe to the power segment smoothly (slope 12.9232, not the standard's 12.92).
  EXPECT_NEAR(image.rgba[4], 0.001 * 12.92, 0.001 * 12.92 * 5e-4);
  EXPECT_NEAR(image.rgba[8], 1.0, 1e-6);
}

TEST(Color, EverySrgbCodeSurvivesARoundTrip) {
  std::vector<float> codes;
  for (int k = 0; k < 256; ++k) codes.push_back(k / 255.0f);
  Image image = singleRow(codes);
  ColorConverter("sRGB", "linear-rec709").apply(image);
  for (int k = 0; k < 256; ++k) EXPECT_NEAR(image.rgba[k * 4], srgbDecode(k / 255.0), 1e-6) << k;
  ColorConverter("linear-rec709", "sRGB").apply(image);
  for (int k = 0; k < 256; ++k) {
    for (int c = 0; c < 3; ++c) EXPECT_EQ(std::lround(image.rgba[k * 4 + c] * 255.0f), k) << k;
  }
}

TEST(Color, Rec709Curve) {
  Image image = singleRow({0.18f, 0.01f, 1.0f});
  ColorConverter("linear-rec709", "rec709").apply(image);
  EXPECT_NEAR(image.rgba[0], rec709Encode(0.18), 1e-5);  // 0.409
  // The smooth join again: slope 4.514 instead of 4.5.
  EXPECT_NEAR(image.rgba[4], 0.045, 0.045 * 5e-3);
  EXPECT_NEAR(image.rgba[8], 1.0, 1e-5);
}

// BT.2020 video: the Rec.709 curve, then BT.2087's matrix to Rec.709 primaries. Encoded 1 in
// green alone is linear BT.2020 green, whose Rec.709 coordinates are the matrix's second
// column; encoded white stays white (the matrix's rows sum to 1).
TEST(Color, Rec2020VideoToLinearRec709) {
  Image image = singleRow({0.0f, 1.0f});
  image.rgba[1] = 1.0f;
  ColorConverter("rec2020", "linear-rec709").apply(image);
  EXPECT_NEAR(image.rgba[0], -0.587641, 1e-4);
  EXPECT_NEAR(image.rgba[1], 1.132900, 1e-4);
  EXPECT_NEAR(image.rgba[2], -0.100579, 1e-4);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(image.rgba[4 + c], 1.0, 1e-4) << c;
}

TEST(Color, AcescgPrimariesAndRoundTrip) {
  Image red = singleRow({0.0f});
  red.rgba[0] = 1.0f;
  ColorConverter("linear-rec709", "ACEScg").apply(red);
  // Rec.709 red in AP1 (Bradford-adapted D65 -> D60).
  EXPECT_NEAR(red.rgba[0], 0.6131, 1e-3);
  EXPECT_NEAR(red.rgba[1], 0.0702, 1e-3);
  EXPECT_NEAR(red.rgba[2], 0.0206, 1e-3);

  Image image(4, 1);
  const float colours[4][3] = {
      {0.18f, 0.18f, 0.18f}, {1.0f, 0.5f, 0.25f}, {0.02f, 0.7f, 0.9f}, {12.0f, 3.0f, 0.5f}};
  for (int p = 0; p < 4; ++p) {
    for (int c = 0; c < 3; ++c) image.rgba[p * 4 + c] = colours[p][c];
  }
  ColorConverter("linear-rec709", "ACEScg").apply(image);
  EXPECT_NEAR(image.rgba[0], 0.18f, 1e-5) << "neutral stays neutral";
  ColorConverter("ACEScg", "linear-rec709").apply(image);
  for (int p = 0; p < 4; ++p) {
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(image.rgba[p * 4 + c], colours[p][c], 1e-5 * std::max(1.0f, colours[p][c]));
  }
}

TEST(Color, AlphaAndPlanesAreUntouched) {
  Image image = singleRow({0.5f, 0.25f});
  image.rgba[3] = 0.3f;
  image.plane("depth") = {7.0f, 8.0f};
  ColorConverter("sRGB", "ACEScg").apply(image);
  EXPECT_EQ(image.rgba[3], 0.3f);
  EXPECT_EQ(image.rgba[7], 1.0f);
  EXPECT_EQ(image.plane("depth"), (std::vector<float>{7.0f, 8.0f}));
}

TEST(Color, FullHdFrameIsConvertedEverywhereAndFast) {
  Image image(1920, 1080);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      float* p = image.pixel(x, y);
      p[0] = y / 1079.0f;
      p[1] = x / 1919.0f;
      p[2] = 0.5f;
      p[3] = 0.25f;
    }
  }
  ColorConverter converter("sRGB", "linear-rec709");
  Image warmUp = image;
  converter.apply(warmUp);
  double bestMs = 1e9;
  for (int run = 0; run < 5; ++run) {
    Image copy = image;
    auto start = std::chrono::steady_clock::now();
    converter.apply(copy);
    bestMs = std::min(
        bestMs, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                    .count());
  }
  std::printf("sRGB -> linear at 1920x1080: %.2f ms\n", bestMs);
  EXPECT_LT(bestMs, 200.0) << "a conversion must not dominate a frame's time";
  converter.apply(image);
  // Every band, first and last rows included.
  for (int y : {0, 1, 269, 270, 540, 1079}) {
    for (int x : {0, 1919}) {
      const float* p = image.pixel(x, y);
      EXPECT_NEAR(p[0], srgbDecode(y / 1079.0), 1e-6) << x << "," << y;
      EXPECT_NEAR(p[1], srgbDecode(x / 1919.0), 1e-6) << x << "," << y;
      EXPECT_EQ(p[3], 0.25f);
    }
  }
}

TEST(Color, NoOps) {
  EXPECT_TRUE(ColorConverter("sRGB", "sRGB").isNoOp());
  EXPECT_TRUE(ColorConverter("sRGB", "srgb").isNoOp()) << "OCIO names are case-insensitive";
  EXPECT_TRUE(ColorConverter("scene_linear", "linear-rec709").isNoOp()) << "roles resolve";
  EXPECT_TRUE(ColorConverter("sRGB", "raw").isNoOp()) << "data is never converted";
  EXPECT_FALSE(ColorConverter("sRGB", "linear-rec709").isNoOp());
  Image image = singleRow({0.5f});
  ColorConverter("linear-rec709", "linear-rec709").apply(image);
  EXPECT_EQ(image.rgba[0], 0.5f);
}

TEST(Color, UnknownColourSpaceIsNamed) {
  try {
    ColorConverter("sRGB", "ProPhoto");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("unknown colour space 'ProPhoto'"), std::string::npos) << message;
    for (const char* known : {"linear-rec709", "ACEScg", "sRGB", "rec709", "raw"}) {
      EXPECT_NE(message.find(known), std::string::npos) << known;
    }
  }
}

TEST(Color, BuiltinNames) {
  EXPECT_EQ(colorSpaceNames(), (std::vector<std::string>{"linear-rec709", "ACEScg", "sRGB",
                                                         "rec709", "rec2020", "raw"}));
}

TEST(Color, SavedBuiltinConfigLoadsBack) {
  const std::filesystem::path path = test::freshTempDir("color_config") / "pluvia.ocio";
  saveBuiltinConfig(path.string());
  ASSERT_TRUE(std::filesystem::exists(path));
  EXPECT_EQ(colorSpaceNames(path.string()), colorSpaceNames());
  Image fromFile = singleRow({0.5f, 0.9f});
  Image builtin = fromFile;
  ColorConverter("sRGB", "ACEScg", path.string()).apply(fromFile);
  ColorConverter("sRGB", "ACEScg").apply(builtin);
  for (size_t i = 0; i < builtin.rgba.size(); ++i)
    EXPECT_NEAR(fromFile.rgba[i], builtin.rgba[i], 1e-7) << i;
}

TEST(Color, MissingConfigFileIsNamed) {
  const std::string path = (test::freshTempDir("color_missing") / "nope.ocio").string();
  try {
    ColorConverter("sRGB", "linear-rec709", path);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

// The table of every code a movie reader looks its samples up in (ColorConverter::codeValues)
// holds, bit for bit, what apply() makes of the same code normalised as the readers normalise it;
// a conversion with channel crosstalk (a primaries matrix) has no table.
TEST(Color, CodeValuesAreWhatApplyGivesEachCode) {
  for (const auto& [from, to] : {std::pair{"sRGB", "linear-rec709"},
                                 {"rec709", "linear-rec709"},
                                 {"linear-rec709", "linear-rec709"}}) {
    const ColorConverter converter(from, to);
    for (int bits : {8, 16}) {
      const std::optional<CodeValues> table = converter.codeValues(bits);
      ASSERT_TRUE(table) << from << " " << bits;
      const int codes = 1 << bits;
      const float scale = 1.0f / float(codes - 1);
      Image ramp(codes, 1);
      for (int k = 0; k < codes; ++k)
        for (int c = 0; c < 3; ++c) ramp.rgba[size_t(k) * 4 + size_t(c)] = float(k) * scale;
      converter.apply(ramp);
      int differing = 0;
      for (int k = 0; k < codes; ++k)
        for (int c = 0; c < 3; ++c)
          differing += (*table)[size_t(c)][size_t(k)] != ramp.rgba[size_t(k) * 4 + size_t(c)];
      EXPECT_EQ(differing, 0) << from << " " << bits;
    }
  }
  EXPECT_FALSE(ColorConverter("sRGB", "ACEScg").codeValues(8));
  EXPECT_FALSE(ColorConverter("sRGB", "linear-rec709").codeValues(10));
}

}  // namespace
}  // namespace pluvia
