// Every shipped preset on real plates nobody tuned it for (../shared/data): the NTURain clip,
// the static street movie, and the weir and Lund photos held still. The render must keep the
// picture (no textured block flattened by fog, darkening or blur) and the rain must cover a
// plausible share of the frame for the preset's rate. Skipped when ../shared/data is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

const std::vector<std::string> kPresets = {"base", "drizzle", "gentle", "moderate",
                                           "hard", "heavy",   "storm"};

struct RealPlate {
  std::string name;
  std::string input;  // relative to ../shared/data
  std::string frame;  // the frame rendered
  double proxy;       // about 320 px wide
};

const std::vector<RealPlate> kPlates = {
    {"nturain", "rain_real/nturain_ra1_real_rain_panning/%05d.jpg", "3", 0.5},
    {"street", "plate_static/opencv_vtest.avi", "2", 0.42},
    {"weir", "stitching/weir/weir_1.jpg", "0", 0.24},
    {"lund", "sfm/opensfm_lund/01.jpg", "0", 0.32},
};

// Luma of an 8-bit sRGB picture read as code / 255, in code values.
std::vector<double> lumaCodes(const Image& image) {
  std::vector<double> luma(image.pixelCount());
  for (size_t i = 0; i < luma.size(); ++i) {
    const float* p = image.rgba.data() + i * 4;
    luma[i] = 255.0 * (0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]);
  }
  return luma;
}

double blockStdDev(const std::vector<double>& luma, int width, int x0, int y0, int size) {
  double sum = 0, sumSq = 0;
  for (int y = y0; y < y0 + size; ++y)
    for (int x = x0; x < x0 + size; ++x) {
      const double v = luma[size_t(y) * width + x];
      sum += v;
      sumSq += v * v;
    }
  const double n = double(size) * size, mean = sum / n;
  return std::sqrt(std::max(0.0, sumSq / n - mean * mean));
}

// The frame as pluvia reads and writes it with no stage at work (the same proxy resize and
// colour round trip), the reference the rained frames are compared with.
stdfs::path renderPlate(const RealPlate& plate, const stdfs::path& dir) {
  const stdfs::path out = dir / (plate.name + "_plate.####.png");
  const auto r = runPluvia({"-q", "render", (sharedData() / plate.input).string(), "-p", "base",
                            "-o", out.string(), "--frames", plate.frame + "-" + plate.frame,
                            "--proxy", std::to_string(plate.proxy), "--set", "rain.enabled=false"});
  EXPECT_EQ(r.exitCode, 0) << r.output;
  return out;
}

stdfs::path frameFile(const stdfs::path& pattern, const std::string& frame) {
  std::string name = pattern.filename().string();
  const size_t hashes = name.find("####");
  std::string number = frame;
  while (number.size() < 4) number = "0" + number;
  name.replace(hashes, 4, number);
  return pattern.parent_path() / name;
}

class RealPlates : public ::testing::TestWithParam<RealPlate> {};

TEST_P(RealPlates, EveryShippedPresetKeepsThePictureAndRains) {
  if (sharedData().empty()) GTEST_SKIP() << "../shared/data is absent";
  const RealPlate& plate = GetParam();
  const stdfs::path dir = freshTempDir("real_plates_" + plate.name);
  const Image reference = readImageFile(frameFile(renderPlate(plate, dir), plate.frame));
  const int width = reference.width, height = reference.height;
  const std::vector<double> plateLuma = lumaCodes(reference);

  std::vector<double> coverage, meanAlpha;
  for (const std::string& preset : kPresets) {
    const stdfs::path out = dir / (plate.name + "_" + preset + ".####.png");
    const auto r = runPluvia({"-q", "render", (sharedData() / plate.input).string(), "-p", preset,
                              "-o", out.string(), "--frames", plate.frame + "-" + plate.frame,
                              "--proxy", std::to_string(plate.proxy), "--aov", "rain"});
    ASSERT_EQ(r.exitCode, 0) << plate.name << " " << preset << ": " << r.output;
    const Image rained = readImageFile(frameFile(out, plate.frame));
    ASSERT_EQ(rained.width, width);
    const std::vector<double> rainedLuma = lumaCodes(rained);

    // No 32x32 block that had texture (std dev > 3 code values) keeps less than 25 % of it
    // (measured worst: `storm` on the weir's foliage, 27 %: its blur of 0.8 px alone keeps 25 %
    // of that fine texture, and at this still's 180-degree shutter its long faint streaks add
    // little back; at 1/600 s they added back 33 %).
    constexpr int kBlock = 32;
    int textured = 0, flattened = 0;
    double worst = 1e9;
    int worstX = 0, worstY = 0;
    for (int y = 0; y + kBlock <= height; y += kBlock)
      for (int x = 0; x + kBlock <= width; x += kBlock) {
        const double before = blockStdDev(plateLuma, width, x, y, kBlock);
        if (before <= 3.0) continue;
        ++textured;
        const double ratio = blockStdDev(rainedLuma, width, x, y, kBlock) / before;
        if (ratio < worst) worst = ratio, worstX = x, worstY = y;
        flattened += ratio < 0.25;
      }
    EXPECT_GT(textured, 10) << plate.name;
    EXPECT_EQ(flattened, 0) << plate.name << " " << preset << ": " << flattened << " of "
                            << textured << " textured blocks flattened (worst ratio " << worst
                            << ")";

    // The rain layer's alpha: the share of pixels it touches by at least 2 code values.
    const stdfs::path rainPattern = dir / (plate.name + "_" + preset + ".rain.####.png");
    const Image rain = readImageFile(frameFile(rainPattern, plate.frame));
    size_t touched = 0;
    double alphaSum = 0.0;
    for (size_t i = 0; i < rain.pixelCount(); ++i) {
      touched += rain.rgba[i * 4 + 3] >= 2.0f / 255.0f;
      alphaSum += rain.rgba[i * 4 + 3];
    }
    const double share = double(touched) / double(rain.pixelCount());
    coverage.push_back(share);
    meanAlpha.push_back(alphaSum / double(rain.pixelCount()));
    std::printf(
        "%s %s: worst block contrast kept %.2f (at %d,%d), rain touches %.1f %% of the pixels, "
        "mean rain "
        "alpha %.4f\n",
        plate.name.c_str(), preset.c_str(), worst, worstX, worstY, 100.0 * share, meanAlpha.back());
  }
  // Plausible for the rate: moderate rain (8 mm/h) touches a per cent at least (drawn only as
  // deep as the camera sees it as streaks, at each plate's own shutter: measured 1.3-6.0 %),
  // drizzle (1.5 mm/h) not most of the frame (0.0-1.7 %: its fine drops' streaks at 1/174 s on
  // the street's walkers are under 2 codes), a storm (100 mm/h) most of it yet stays a veil one
  // sees through (its mean alpha is a few times the projected area of its drops, about 0.02),
  // and heavier rain touches more.
  const auto index = [&](const std::string& preset) {
    return size_t(std::find(kPresets.begin(), kPresets.end(), preset) - kPresets.begin());
  };
  const auto at = [&](const std::string& preset) { return coverage[index(preset)]; };
  EXPECT_GT(at("moderate"), 0.01) << plate.name;
  EXPECT_LT(at("drizzle"), 0.5) << plate.name;
  EXPECT_GT(at("storm"), 0.3) << plate.name;
  EXPECT_LT(meanAlpha[index("storm")], 0.2) << plate.name;
  EXPECT_LE(at("drizzle"), at("gentle")) << plate.name;
  EXPECT_LT(at("gentle"), at("hard")) << plate.name;
  EXPECT_LT(at("hard"), at("storm")) << plate.name;
}

INSTANTIATE_TEST_SUITE_P(SharedData, RealPlates, ::testing::ValuesIn(kPlates),
                         [](const auto& info) { return info.param.name; });

}  // namespace
