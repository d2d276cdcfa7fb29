// Night rain made of light, with a shipped preset at its default options: a frame of the real
// street footage darkened to night, two clipped lamps painted on it over a depth card 8 m away,
// found by lights.find (auto). The rain AOV's streaks within a lamp's reach are at least 3x as
// bright as far from the lamps (the drops are lit by the lamps; a night plate's dark sky lights
// little), each found lamp is placed within 20 % of the depth of the surface around it, and no
// pixel of a photographed lamp is brightened by glare (the plate holds the bloom its camera gave
// it). Skipped without ../shared/data.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include "night_plate.h"
#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

constexpr int kWidth = 256, kHeight = 192;
constexpr double kCardMeters = 8.0;
constexpr double kLampRadiusPx = 7.0;  // the painted glow's radius
const std::vector<PixelXY> kLamps{{60.5, 50.5}, {190.5, 70.5}};

std::string nightPlateWithLamps(const stdfs::path& dir) {
  return writeStreetPlate(dir, 0.06f, [](Image& image) {
    for (const PixelXY& lamp : kLamps)
      for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
          const double r = std::hypot(x + 0.5 - lamp[0], y + 0.5 - lamp[1]);
          float* p = image.pixel(x, y);
          for (int c = 0; c < 3; ++c)
            if (r <= 3.0)
              p[c] = 1.0f;  // a clipped core
            else if (r <= kLampRadiusPx)
              p[c] = c == 2 ? 0.3f : 0.6f;  // a warm glow around it
        }
  });
}

}  // namespace

TEST(CliNightRain, LampsLightTheRainAtTheirDepthWithoutASecondBloom) {
  if (!haveStreetMovie()) GTEST_SKIP() << "../shared/data is absent";
  const stdfs::path dir = freshTempDir("night_rain");
  const std::string plate = nightPlateWithLamps(dir);
  const stdfs::path out = dir / "night.####.exr";
  const auto rendered = runPluvia({"render", plate, "-p", "heavy", "-o", out.string(), "--frames",
                                   "1-1", "--aov", "rain,glare", "--set", "depth.source=layers",
                                   "--set", "depth.layers=[{\"type\":\"card\",\"distance_m\":8}]"});
  ASSERT_EQ(rendered.exitCode, 0) << rendered.output;
  EXPECT_NE(rendered.output.find("2 lights found in the plate"), std::string::npos)
      << rendered.output;
  // A still without metadata: the 180-degree shutter at the sequence's 24 fps.
  EXPECT_NE(
      rendered.output.find("rain: shutter 1/48 s, the 180-degree shutter at the plate's 24 fps"),
      std::string::npos)
      << rendered.output;

  // Each lamp at the depth of the card around it.
  const std::regex line(R"(found at \(([-0-9.]+), ([-0-9.]+)\) px, [0-9]+ px, ([0-9.]+) m deep)");
  int placed = 0;
  for (auto it = std::sregex_iterator(rendered.output.begin(), rendered.output.end(), line);
       it != std::sregex_iterator(); ++it) {
    ++placed;
    EXPECT_NEAR(std::stod((*it)[3]), kCardMeters, 0.2 * kCardMeters) << it->str();
  }
  EXPECT_EQ(placed, 2) << rendered.output;

  // Streaks near the lamps glint; far from them the night shows little rain.
  const Image rain = readAov(dir / "night.0001.exr", "rain", dir);
  const NearFarRadiance streaks = streakRadianceNearFar(
      rain, [](const float* p) { return (p[0] + p[1] + p[2]) / p[3]; }, kLamps, 25.0, kLamps, 80.0);
  ASSERT_GT(streaks.nearCount, 10);
  ASSERT_GT(streaks.farCount, 10);
  EXPECT_GT(streaks.nearMean, 3.0 * streaks.farMean)
      << "near " << streaks.nearMean << " far " << streaks.farMean;

  // The glare AOV adds nothing to the photographed lamps' pixels.
  const Image glare = readAov(dir / "night.0001.exr", "glare", dir);
  double brightest = 0.0;
  for (const PixelXY& lamp : kLamps)
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x)
        if (std::hypot(x + 0.5 - lamp[0], y + 0.5 - lamp[1]) <= kLampRadiusPx)
          for (int c = 0; c < 3; ++c) brightest = std::max(brightest, double(glare.pixel(x, y)[c]));
  EXPECT_LE(brightest, 1e-6) << "glare added " << brightest << " to a photographed lamp";
}
