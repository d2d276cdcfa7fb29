// Lights found in the plate (lights.find auto): a frame of the real street movie in
// ../shared/data darkened to night, with clipped lamp discs of known colour painted at known
// pixels on a depth card 8 m away. The log must list a light within 2 px of each disc with the
// disc's hue, and the rain AOV must be brighter near the lamps than far from them. The same
// plate without lamps finds none. Skipped when ../shared/data is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <regex>

#include <nlohmann/json.hpp>

#include "night_plate.h"
#include "test_support.h"
#include "util/subprocess.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

double srgbToLinear(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

constexpr int kWidth = 256, kHeight = 192;

struct Lamp {
  double x, y;               // disc centre, pixels (centres at +0.5)
  std::array<float, 3> rgb;  // the rim's colour, max channel 1
};
const std::vector<Lamp> kLamps{{60.5, 50.5, {1.0f, 0.6f, 0.2f}}, {190.5, 70.5, {0.3f, 0.6f, 1.0f}}};

std::string nightPlate(const stdfs::path& dir, bool withLamps) {
  return writeStreetPlate(dir, 0.06f, [&](Image& image) {
    if (!withLamps) return;
    for (const Lamp& lamp : kLamps)
      for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
          const double r = std::hypot(x + 0.5 - lamp.x, y + 0.5 - lamp.y);
          float* p = image.pixel(x, y);
          // A clipped white core of radius 3 px in a coloured glow out to 7 px.
          for (int c = 0; c < 3; ++c)
            if (r <= 3.0)
              p[c] = 1.0f;
            else if (r <= 7.0)
              p[c] = 0.5f * lamp.rgb[size_t(c)];
        }
  });
}

stdfs::path preset(const stdfs::path& dir) {
  return writeTextFile(dir, "night.json", R"({
    "pluvia": 1, "extends": "base",
    "camera": {"fov_deg": 50, "exposure_s": 0.02, "f_number": 0, "focus_m": 0},
    "depth": {"source": "layers", "layers": [{"type": "card", "distance_m": 8}]},
    "fog": {"density": 0.02, "color_source": "constant", "color": [0, 0, 0]},
    "rain": {"rate_mm_h": 60, "far_m": 8, "seed": 3}
  })");
}

// Calls `check(match, lamp)` for each match of `line` in `output` whose first two groups are a
// pixel within 2 px of one of the lamps; returns how many were.
int forEachLampFound(const std::string& output, const std::regex& line,
                     const std::function<void(const std::smatch&, const Lamp&)>& check) {
  int matched = 0;
  for (auto it = std::sregex_iterator(output.begin(), output.end(), line);
       it != std::sregex_iterator(); ++it) {
    const double x = std::stod((*it)[1]), y = std::stod((*it)[2]);
    for (const Lamp& lamp : kLamps) {
      if (std::hypot(x - lamp.x, y - lamp.y) > 2.0) continue;
      ++matched;
      check(*it, lamp);
    }
  }
  return matched;
}

}  // namespace

TEST(CliPlateLights, ClippedDiscsBecomeLightsThatLightTheRain) {
  if (!haveStreetMovie()) GTEST_SKIP() << "../shared/data is absent";
  const stdfs::path dir = freshTempDir("plate_lights");
  const std::string plate = nightPlate(dir, true);
  const stdfs::path out = dir / "night.####.exr";
  const auto rendered = runPluvia({"render", plate, "-p", preset(dir).string(), "-o", out.string(),
                                   "--frames", "1-1", "--aov", "rain,lights"});
  ASSERT_EQ(rendered.exitCode, 0) << rendered.output;
  EXPECT_NE(rendered.output.find("2 lights found in the plate"), std::string::npos)
      << rendered.output;
  // "found at (x, y) px, A px: world (..) m, colour (r, g, b)": one per disc.
  const std::regex line(
      R"(found at \(([-0-9.]+), ([-0-9.]+)\) px.*colour \(([0-9.]+), ([0-9.]+), ([0-9.]+)\))");
  const int matched =
      forEachLampFound(rendered.output, line, [](const std::smatch& found, const Lamp& lamp) {
        // The hue: the rim's colour in the working space (the plate's PNG code values 0.5 * rgb
        // decoded by the sRGB curve), each channel within 0.05.
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(std::stod(found[size_t(3 + c)]),
                      srgbToLinear(0.5 * lamp.rgb[size_t(c)]) / srgbToLinear(0.5), 0.05)
              << c;
      });
  EXPECT_EQ(matched, 2) << rendered.output;

  const Image rain = readAov(dir / "night.0001.exr", "rain", dir);
  std::vector<PixelXY> lamps;
  for (const Lamp& lamp : kLamps) lamps.push_back({lamp.x, lamp.y});
  const NearFarRadiance streaks = streakRadianceNearFar(
      rain, [](const float* p) { return (p[0] + p[1] + p[2]) / p[3]; }, lamps, 25.0, lamps, 80.0);
  ASSERT_GT(streaks.nearCount, 10);
  ASSERT_GT(streaks.farCount, 10);
  EXPECT_GT(streaks.nearMean, 3.0 * streaks.farMean)
      << "near " << streaks.nearMean << " far " << streaks.farMean;
}

TEST(CliPlateLights, NothingClippedFindsNoLights) {
  if (!haveStreetMovie()) GTEST_SKIP() << "../shared/data is absent";
  const stdfs::path dir = freshTempDir("plate_lights_none");
  const std::string plate = nightPlate(dir, false);
  const auto rendered = runPluvia({"render", plate, "-p", preset(dir).string(), "-o",
                                   (dir / "out.####.exr").string(), "--frames", "1-1"});
  ASSERT_EQ(rendered.exitCode, 0) << rendered.output;
  EXPECT_NE(rendered.output.find("0 lights found in the plate"), std::string::npos)
      << rendered.output;
  EXPECT_NE(rendered.output.find("the light work is skipped"), std::string::npos);
  const auto plan = runPluvia({"plan", plate, "-p", preset(dir).string()});
  ASSERT_EQ(plan.exitCode, 0) << plan.output;
  EXPECT_NE(plan.output.find("looked for in the plate when the render prepares"), std::string::npos)
      << plan.output;
}

TEST(CliPlateLights, PlanResolvedListsTheFoundLamps) {
  // `pluvia plan --resolved` finds the lamps as a render does (once per clip: the still, the
  // depth of the first frame) and lists each: pixel within 2 px of its disc, the card's 8 m
  // depth, the disc's hue, an intensity; the resolved preset still follows as JSON.
  if (!haveStreetMovie()) GTEST_SKIP() << "../shared/data is absent";
  const stdfs::path dir = freshTempDir("plate_lights_plan");
  const std::string plate = nightPlate(dir, true);
  const auto planned = runPluvia({"plan", plate, "-p", preset(dir).string(), "--resolved"});
  ASSERT_EQ(planned.exitCode, 0) << planned.output;
  EXPECT_NE(planned.output.find("lamps found in the plate (lights.find): 2"), std::string::npos)
      << planned.output;
  const std::regex line(
      R"(lamp \d: pixel \(([-0-9.]+), ([-0-9.]+)\), \d+ px, depth ([0-9.]+) m, colour \(([0-9.]+), ([0-9.]+), ([0-9.]+)\), intensity ([0-9.e+-]+))");
  const int matched =
      forEachLampFound(planned.output, line, [](const std::smatch& found, const Lamp& lamp) {
        EXPECT_NEAR(std::stod(found[3]), 8.0, 1e-6);
        // The rim's colour after the sRGB decode: its channels' order is the disc's.
        const std::array<double, 3> rgb{std::stod(found[4]), std::stod(found[5]),
                                        std::stod(found[6])};
        const size_t brightest = size_t(std::max_element(rgb.begin(), rgb.end()) - rgb.begin());
        EXPECT_EQ(brightest,
                  size_t(std::max_element(lamp.rgb.begin(), lamp.rgb.end()) - lamp.rgb.begin()));
        EXPECT_GT(std::stod(found[7]), 0.0);
      });
  EXPECT_EQ(matched, 2) << planned.output;
  // stdout alone is the JSON (the lamps go to stderr), so a script can load it as it is.
  const auto stdoutOnly =
      runProcess({"sh", "-c", "\"$0\" plan \"$1\" -p \"$2\" --resolved 2>/dev/null",
                  pluviaBinary().string(), plate, preset(dir).string()});
  ASSERT_EQ(stdoutOnly.exitCode, 0) << stdoutOnly.output;
  const auto json = nlohmann::json::parse(stdoutOnly.output);
  EXPECT_EQ(json["lights"]["find"], "auto");
}
