// Stroke libraries on disk (src/rain/stroke_library.h): LIBRARY.json + a 16-bit PNG atlas.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "rain/stroke_library.h"
#include "test_support.h"
#include "util/error.h"
#include "util/fs.h"

using namespace pluvia;
namespace stdfs = std::filesystem;

namespace {

// Two strokes in a 12 x 20 atlas with 2 px of zeros around each.
rain::StrokeLibrary smallLibrary() {
  rain::StrokeLibrary library;
  library.atlas.width = 12;
  library.atlas.height = 20;
  library.atlas.alpha.assign(12 * 20, 0.0f);
  auto stroke = [&](int x, int y, int w, int h, double length, int64_t frame) {
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i)
        library.atlas.alpha[size_t(y + j) * 12 + x + i] =
            float(std::exp(-0.5 * std::pow(i - (w - 1) / 2.0, 2)) * (0.3 + 0.7 * j / (h - 1)));
    rain::StrokeInfo info;
    info.x = x, info.y = y, info.width = w, info.height = h;
    info.lengthPx = length;
    info.widthPx = 1.7;
    info.contrast = 0.42;
    info.sourceFrame = frame;
    info.score = 1.25;
    library.strokes.push_back(info);
    library.atlas.rects.push_back({float(x), float(y), float(x + w), float(y + h)});
  };
  stroke(2, 2, 3, 16, 15.5, 1001);
  stroke(7, 2, 3, 10, 9.25, 1002);
  library.source = "rain.%05d.jpg";
  library.command = "pluvia strokes rain.%05d.jpg -o lib.json";
  return library;
}

std::string errorOf(const std::string& path) {
  try {
    rain::loadStrokeLibrary(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

nlohmann::json readJson(const stdfs::path& path) {
  return nlohmann::json::parse(fs::readTextFile(path));
}

// Written as another program would: this process has read the file, so pluvia's own writer
// refuses to write over it (util/input_guard.h).
void writeJson(const stdfs::path& path, const nlohmann::json& json) {
  std::ofstream(path) << json.dump();
}

}  // namespace

TEST(StrokeLibrary, SaveLoadRoundTrip) {
  const stdfs::path dir = test::freshTempDir("stroke_library_round_trip");
  const rain::StrokeLibrary saved = smallLibrary();
  // Saving over another library replaces both files (the load below reads the second).
  rain::StrokeLibrary first = saved;
  first.source = "other";
  rain::saveStrokeLibrary(first, (dir / "lib.json").string());
  rain::saveStrokeLibrary(saved, (dir / "lib.json").string());
  ASSERT_TRUE(stdfs::is_regular_file(dir / "lib.png"));
  // Nothing left behind but the two files.
  EXPECT_EQ(std::distance(stdfs::directory_iterator(dir), stdfs::directory_iterator()), 2);
  const cv::Mat png = cv::imread((dir / "lib.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(png.type(), CV_16UC1);

  const rain::StrokeLibrary loaded = rain::loadStrokeLibrary((dir / "lib.json").string());
  EXPECT_EQ(loaded.source, saved.source);
  EXPECT_EQ(loaded.command, saved.command);
  ASSERT_EQ(loaded.atlas.width, saved.atlas.width);
  ASSERT_EQ(loaded.atlas.height, saved.atlas.height);
  ASSERT_EQ(loaded.atlas.alpha.size(), saved.atlas.alpha.size());
  for (size_t i = 0; i < saved.atlas.alpha.size(); ++i)
    ASSERT_NEAR(loaded.atlas.alpha[i], saved.atlas.alpha[i], 0.5 / 65535.0 + 1e-7) << i;
  EXPECT_EQ(loaded.atlas.rects, saved.atlas.rects);
  ASSERT_EQ(loaded.strokes.size(), saved.strokes.size());
  for (size_t i = 0; i < saved.strokes.size(); ++i) {
    const auto &a = loaded.strokes[i], &b = saved.strokes[i];
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.lengthPx, b.lengthPx);
    EXPECT_EQ(a.widthPx, b.widthPx);
    EXPECT_EQ(a.contrast, b.contrast);
    EXPECT_EQ(a.sourceFrame, b.sourceFrame);
    EXPECT_EQ(a.score, b.score);
  }
  // A library this run read is an input: never saved over by it.
  EXPECT_THROW(rain::saveStrokeLibrary(first, (dir / "lib.json").string()), pluvia::Error);
}

TEST(StrokeLibrary, ErrorsNameTheFile) {
  const stdfs::path dir = test::freshTempDir("stroke_library_errors");
  const std::string missing = (dir / "missing.json").string();
  EXPECT_NE(errorOf(missing).find(missing), std::string::npos) << errorOf(missing);

  const stdfs::path bad = dir / "bad.json";
  fs::writeTextFile(bad, "{\"pluvia_strokes\": 1, \"atlas\": ");
  EXPECT_NE(errorOf(bad.string()).find(bad.string()), std::string::npos);
  EXPECT_NE(errorOf(bad.string()).find("JSON"), std::string::npos) << errorOf(bad.string());

  rain::saveStrokeLibrary(smallLibrary(), (dir / "lib.json").string());
  const nlohmann::json good = readJson(dir / "lib.json");

  // A key missing: the key is named.
  nlohmann::json noWidth = good;
  noWidth.erase("width");
  writeJson(dir / "lib.json", noWidth);
  std::string message = errorOf((dir / "lib.json").string());
  EXPECT_NE(message.find((dir / "lib.json").string()), std::string::npos) << message;
  EXPECT_NE(message.find("width"), std::string::npos) << message;

  // A rectangle outside the atlas: the stroke is named.
  nlohmann::json outside = good;
  outside["strokes"][1]["rect"] = {10, 2, 3, 10};
  writeJson(dir / "lib.json", outside);
  message = errorOf((dir / "lib.json").string());
  EXPECT_NE(message.find((dir / "lib.json").string()), std::string::npos) << message;
  EXPECT_NE(message.find("stroke 1"), std::string::npos) << message;
  EXPECT_NE(message.find("outside"), std::string::npos) << message;

  // A stroke with a key of the wrong type.
  nlohmann::json wrongType = good;
  wrongType["strokes"][0]["score"] = "high";
  writeJson(dir / "lib.json", wrongType);
  message = errorOf((dir / "lib.json").string());
  EXPECT_NE(message.find("stroke 0"), std::string::npos) << message;
  EXPECT_NE(message.find("score"), std::string::npos) << message;

  // The JSON's size is not the atlas PNG's.
  nlohmann::json otherSize = good;
  otherSize["height"] = 24;
  writeJson(dir / "lib.json", otherSize);
  message = errorOf((dir / "lib.json").string());
  EXPECT_NE(message.find((dir / "lib.json").string()), std::string::npos) << message;
  EXPECT_NE(message.find("12x20"), std::string::npos) << message;

  // No strokes.
  nlohmann::json none = good;
  none["strokes"] = nlohmann::json::array();
  writeJson(dir / "lib.json", none);
  message = errorOf((dir / "lib.json").string());
  EXPECT_NE(message.find("no strokes"), std::string::npos) << message;

  // The atlas missing, or not 16-bit.
  writeJson(dir / "lib.json", good);
  stdfs::remove(dir / "lib.png");
  message = errorOf((dir / "lib.json").string());
  EXPECT_NE(message.find((dir / "lib.json").string()), std::string::npos) << message;
  EXPECT_NE(message.find("lib.png"), std::string::npos) << message;
  cv::imwrite((dir / "lib.png").string(), cv::Mat::zeros(20, 12, CV_8UC1));
  message = errorOf((dir / "lib.json").string());
  EXPECT_NE(message.find("16-bit"), std::string::npos) << message;
}

TEST(StrokeLibrary, SaveRefusesAnEmptyLibrary) {
  const stdfs::path dir = test::freshTempDir("stroke_library_empty");
  rain::StrokeLibrary empty = smallLibrary();
  empty.strokes.clear();
  empty.atlas.rects.clear();
  EXPECT_THROW(rain::saveStrokeLibrary(empty, (dir / "lib.json").string()), Error);
  EXPECT_FALSE(stdfs::exists(dir / "lib.json"));
  EXPECT_FALSE(stdfs::exists(dir / "lib.png"));
}

TEST(StrokeLibrary, AtlasJsonForTheCacheRoundTrips) {
  const rain::StrokeAtlas atlas = smallLibrary().atlas;
  const rain::StrokeAtlas back = rain::strokeAtlasFromJson(rain::strokeAtlasToJson(atlas), "cache");
  EXPECT_EQ(back.width, atlas.width);
  EXPECT_EQ(back.height, atlas.height);
  EXPECT_EQ(back.alpha, atlas.alpha);
  EXPECT_EQ(back.rects, atlas.rects);
  nlohmann::json outside = rain::strokeAtlasToJson(atlas);
  outside["rects"][0] = {0, 0, 13, 4};
  try {
    rain::strokeAtlasFromJson(outside, "cache/derain/key.json");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.context().file, "cache/derain/key.json");
  }
}

TEST(StrokeLibrary, BuiltinIsFoundAndHonoursTheAssetFolder) {
  const std::string builtin = rain::builtinStrokeLibraryPath();
  EXPECT_TRUE(stdfs::is_regular_file(builtin)) << builtin;
  EXPECT_EQ(stdfs::path(builtin).filename(), "builtin.json");

  const stdfs::path dir = test::freshTempDir("stroke_library_asset_dir");
  rain::saveStrokeLibrary(smallLibrary(), (dir / "strokes" / "builtin.json").string());
  rain::setAssetFolder(dir);
  const std::string overridden = rain::builtinStrokeLibraryPath();
  rain::setAssetFolder({});
  EXPECT_EQ(overridden, (dir / "strokes" / "builtin.json").string());
  EXPECT_EQ(rain::builtinStrokeLibraryPath(), builtin);
}

// The shipped library: real strokes, upright and elongated.
TEST(StrokeLibrary, BuiltinHoldsUprightElongatedStrokes) {
  const rain::StrokeLibrary library = rain::loadStrokeLibrary(rain::builtinStrokeLibraryPath());
  ASSERT_GE(library.strokes.size(), 32u);
  EXPECT_LE(library.atlas.width, 1024);
  EXPECT_FALSE(library.source.empty());
  EXPECT_FALSE(library.command.empty());
  const cv::Mat atlas(library.atlas.height, library.atlas.width, CV_32FC1,
                      const_cast<float*>(library.atlas.alpha.data()));
  for (size_t i = 0; i < library.strokes.size(); ++i) {
    const auto& s = library.strokes[i];
    const cv::Mat matte = atlas(cv::Rect(s.x, s.y, s.width, s.height));
    double peak = 0.0;
    cv::minMaxLoc(matte, nullptr, &peak);
    EXPECT_NEAR(peak, 1.0, 1e-4) << "stroke " << i;
    const cv::Moments m = cv::moments(matte, false);
    // Principal axis within 5 degrees of the vertical, and clearly elongated along it.
    const double tilt = 0.5 * std::atan2(2.0 * m.mu11, m.mu02 - m.mu20) * 180.0 / M_PI;
    EXPECT_LT(std::abs(tilt), 5.0) << "stroke " << i;
    const double spread = std::sqrt(4.0 * m.mu11 * m.mu11 + (m.mu20 - m.mu02) * (m.mu20 - m.mu02));
    const double major = 0.5 * (m.mu20 + m.mu02 + spread), minor = 0.5 * (m.mu20 + m.mu02 - spread);
    EXPECT_GT(major, 4.0 * minor) << "stroke " << i;  // axes' ratio above 2
    EXPECT_GT(s.height, s.width) << "stroke " << i;
    EXPECT_GE(s.lengthPx, 9.0) << "stroke " << i;  // StrokeExtractionSettings::minLengthPx
    EXPECT_GT(s.contrast, 0.0) << "stroke " << i;
    if (i > 0) {
      EXPECT_LE(s.score, library.strokes[i - 1].score) << "stroke " << i;
    }
  }
}

// A box stroke 2 px wide and 10 px long in a 6 x 20 rectangle (soft margins of zeros): the quad
// must grow 3x across and 2x along so that the stroke, not its rectangle, spans the streak. The
// builtin library's strokes, cut from footage with their soft sides, all ask for growth.
TEST(StrokeLibrary, QuadScalesAreTheRectangleOverTheStrokesOwnSize) {
  rain::StrokeAtlas atlas;
  atlas.width = 8;
  atlas.height = 24;
  atlas.alpha.assign(size_t(atlas.width * atlas.height), 0.0f);
  for (int y = 7; y < 17; ++y)
    for (int x = 3; x < 5; ++x) atlas.alpha[size_t(y * atlas.width + x)] = 1.0f;
  atlas.rects = {{1, 2, 7, 22}, {0, 0, 0, 0}};
  const auto scales = rain::strokeQuadScales(atlas);
  ASSERT_EQ(scales.size(), 2u);
  EXPECT_NEAR(scales[0][0], 3.0, 1e-6);  // 6 / 2 across
  EXPECT_NEAR(scales[0][1], 2.0, 1e-6);  // 20 / 10 along (half-maximum length of a box)
  EXPECT_EQ(scales[1][0], 1.0f);         // an empty rectangle is left as it is
  EXPECT_EQ(scales[1][1], 1.0f);

  const rain::StrokeLibrary builtin = rain::loadStrokeLibrary(rain::builtinStrokeLibraryPath());
  for (const auto& scale : rain::strokeQuadScales(builtin.atlas)) {
    EXPECT_GT(scale[0], 1.1f);
    EXPECT_GT(scale[1], 1.1f);
    EXPECT_LT(scale[1], 3.0f);
  }
}
