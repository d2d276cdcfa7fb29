// A night plate built from real footage (a frame of the static street movie in ../shared/data,
// darkened to night), two lamps placed in it: a point lamp and a spotlight pointing down. The
// lights AOV must show a halo centred on the point lamp and the spot's beam below it (not above),
// and on the rain AOV (--aov rain) the streaks near the lamp must be brighter than those far
// from both lamps. Skipped when ../shared/data is absent.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "night_plate.h"
#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

constexpr int kWidth = 256, kHeight = 192;
constexpr double kHfovDeg = 50.0;

// Where a camera-space point lands in the frame (camera at the origin, no tilt).
std::pair<double, double> project(double x, double y, double z) {
  const double f = 0.5 * kWidth / std::tan(0.5 * kHfovDeg * M_PI / 180.0);
  return {0.5 * kWidth + f * x / -z, 0.5 * kHeight - f * y / -z};
}

}  // namespace

TEST(CliNightLights, HalosBeamsAndLitStreaksOnADarkenedStreet) {
  if (!haveStreetMovie()) GTEST_SKIP() << "../shared/data is absent";
  const stdfs::path dir = freshTempDir("night_lights");
  // Frame 2 of the street movie at 256 x 192, then a night of it: x 0.06 in code values.
  const std::string plate = writeStreetPlate(dir, 0.06f);
  // Point lamp left of centre 6 m away; a spot 9 m away, right, pointing straight down.
  const auto lamp = project(-1.2, 0.6, -6.0);
  const auto spot = project(1.8, 1.2, -9.0);
  const stdfs::path preset = writeTextFile(dir, "night.json", R"({
    "pluvia": 1, "extends": "base",
    "camera": {"fov_deg": 50, "exposure_s": 0.02, "f_number": 0, "focus_m": 0},
    "depth": {"source": "none"},
    "fog": {"density": 0.03, "color_source": "constant", "color": [0, 0, 0]},
    "rain": {"rate_mm_h": 60, "far_m": 10, "seed": 3, "opacity": 3},
    "lights": {"list": [
      {"type": "point", "x_m": -1.2, "y_m": 0.6, "z_m": -6, "intensity": 40,
       "color": [1.0, 0.8, 0.55]},
      {"type": "spot", "x_m": 1.8, "y_m": 1.2, "z_m": -9, "intensity": 150,
       "dir_x": 0, "dir_y": -1, "dir_z": 0, "half_angle_deg": 20, "falloff_q": 0.3,
       "color": [0.8, 0.9, 1.0]}]}
  })");
  const stdfs::path out = dir / "night.####.exr";
  const auto rendered = runPluvia({"-q", "render", plate, "-p", preset.string(), "-o", out.string(),
                                   "--frames", "1-1", "--aov", "rain,lights"});
  ASSERT_EQ(rendered.exitCode, 0) << rendered.output;
  const Image lights = readAov(dir / "night.0001.exr", "lights", dir);
  const Image rain = readAov(dir / "night.0001.exr", "rain", dir);
  ASSERT_EQ(lights.width, kWidth);

  // The halo: the brightest lights pixel within 30 px of the point lamp sits on it.
  float best = -1.0f;
  int bx = 0, by = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      if (std::hypot(x + 0.5 - lamp.first, y + 0.5 - lamp.second) > 30.0) continue;
      if (lights.pixel(x, y)[1] > best) best = lights.pixel(x, y)[1], bx = x, by = y;
    }
  // The halo is flat across the bulb's image (optics/single_scattering.cpp: a ray passing
  // within radius_m of the light sees it moved out to the radius), 0.05 m at 6 m = 2.3 px here:
  // the single brightest pixel lands anywhere on that plateau (it was 2.1 px off), so its
  // centre is the centroid of the pixels within 2 % of the peak.
  double sx = 0, sy = 0;
  int n = 0;
  for (int y = std::max(0, by - 6); y <= std::min(kHeight - 1, by + 6); ++y)
    for (int x = std::max(0, bx - 6); x <= std::min(kWidth - 1, bx + 6); ++x)
      if (lights.pixel(x, y)[1] >= 0.98f * best) sx += x + 0.5, sy += y + 0.5, ++n;
  EXPECT_LE(std::hypot(sx / n - lamp.first, sy / n - lamp.second), 1.0)
      << sx / n << "," << sy / n << " vs " << lamp.first << "," << lamp.second;

  // The beam: 10 to 40 px below the spot against the same above it.
  auto columnMean = [&](int from, int to) {
    double sum = 0;
    int n = 0;
    for (int dy = from; dy <= to; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const int x = int(spot.first) + dx, y = int(spot.second) + dy;
        if (x < 0 || x >= kWidth || y < 0 || y >= kHeight) continue;
        sum += lights.pixel(x, y)[2];
        ++n;
      }
    return sum / std::max(n, 1);
  };
  const double below = columnMean(10, 40), above = columnMean(-40, -10);
  EXPECT_GT(below, 5.0 * above + 1e-6) << below << " " << above;

  // The streaks: their radiance (rain.G / rain.A where a streak covers the pixel) near the
  // lamp against far from both lamps.
  const NearFarRadiance streaks = streakRadianceNearFar(
      rain, [](const float* p) { return p[1] / p[3]; }, {{lamp.first, lamp.second}}, 25.0,
      {{lamp.first, lamp.second}, {spot.first, spot.second}}, 90.0);
  ASSERT_GT(streaks.nearCount, 20);
  ASSERT_GT(streaks.farCount, 20);
  std::cout << "streak radiance near " << streaks.nearMean << " far " << streaks.farMean
            << " beam below " << below << " above " << above << "\n";
  EXPECT_GT(streaks.nearMean, 3.0 * streaks.farMean)
      << "near " << streaks.nearMean << " (" << streaks.nearCount << ") far " << streaks.farMean
      << " (" << streaks.farCount << ")";
}
