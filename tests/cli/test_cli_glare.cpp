// Glare (lights.glare, stages/glare_stage.cpp) end to end on plates made from a real frame (the
// street movie in ../shared/data): on a darkened street with one lamp, the glare AOV is the CIE
// veil of the lamp's irradiance at the camera at several angles; on the street by day, without
// lights, the default (auto) leaves every pixel as lights.glare = off does. Skipped when
// ../shared/data is absent.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>

#include "night_plate.h"
#include "optics/glare.h"
#include "test_support.h"

using namespace pluvia;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

constexpr int kWidth = 256, kHeight = 192;

}  // namespace

TEST(CliGlare, TheVeilOfALampIsTheCieKernel) {
  if (!haveStreetMovie()) GTEST_SKIP() << "../shared/data is absent";
  const stdfs::path dir = freshTempDir("glare_night");
  const std::string plate = writeStreetPlate(dir, 0.06f);
  // A lamp of intensity 20 straight ahead 5 m away in thin fog (0.005 /m: its halo stays under
  // 1.0 outside the bulb, so the lamp alone glares); no rain.
  const stdfs::path preset = writeTextFile(dir, "night.json", R"({
    "pluvia": 1, "extends": "base",
    "camera": {"fov_deg": 50, "tilt_deg": 0},
    "depth": {"source": "none"},
    "fog": {"density": 0.005, "color_source": "constant", "color": [0, 0, 0]},
    "rain": {"rate_mm_h": 0},
    "lights": {"find": "off", "list": [
      {"type": "point", "x_m": 0, "y_m": 0, "z_m": -5, "intensity": 20, "color": [1, 1, 1]}]}
  })");
  const auto rendered =
      runPluvia({"-q", "render", plate, "-p", preset.string(), "-o",
                 (dir / "night.####.exr").string(), "--frames", "1-1", "--aov", "glare"});
  ASSERT_EQ(rendered.exitCode, 0) << rendered.output;
  const Image glare = readAov(dir / "night.0001.exr", "glare", dir);
  ASSERT_EQ(glare.width, kWidth);
  // The lamp's irradiance at the camera, and the veil the kernel gives it theta away:
  // E PSF(theta) cos^3(theta) (a pixel's weight PSF cos^3 / f^2 times the splat E f^2).
  const double f = 0.5 * kWidth / std::tan(25.0 * M_PI / 180.0);
  const double irradiance = 20.0 * std::exp(-0.005 * 5.0) / 25.0;
  const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
  for (double r : {6.0, 15.0, 40.0, 90.0}) {
    double sum = 0.0, expected = 0.0;
    int n = 0;
    for (int y = 0; y < kHeight; ++y)
      for (int x = 0; x < kWidth; ++x) {
        const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
        if (d < 0.95 * r || d >= 1.05 * r) continue;
        sum += glare.pixel(x, y)[1];
        expected += irradiance * optics::glareKernelWeight(d, f) * f * f;
        ++n;
      }
    expected /= n;
    std::cout << "veil at " << r << " px: " << sum / n << ", the kernel's " << expected << "\n";
    // 15 %: the pyramid's fit (1.6 % mean), the ring's width, the splat's sub-pixel spread.
    EXPECT_NEAR(sum / n / expected, 1.0, 0.15)
        << "at " << r << " px: " << sum / n << " vs " << expected;
  }
}

TEST(CliGlare, AutoLeavesADayPlateWithoutLightsAlone) {
  if (!haveStreetMovie()) GTEST_SKIP() << "../shared/data is absent";
  const stdfs::path dir = freshTempDir("glare_day");
  const std::string plate = writeStreetPlate(dir, 1.0f);
  auto render = [&](const std::string& name, const std::vector<std::string>& extra) {
    std::vector<std::string> args{
        "-q",       "render", plate, "-p", "moderate", "-o", (dir / (name + ".####.exr")).string(),
        "--frames", "1-1"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = runPluvia(args);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    return readImageFile(dir / (name + ".0001.exr"));
  };
  const Image byDefault = render("auto", {});
  const Image off = render("off", {"--set", "lights.glare=off"});
  ASSERT_EQ(byDefault.rgba.size(), off.rgba.size());
  EXPECT_EQ(std::memcmp(byDefault.rgba.data(), off.rgba.data(), off.rgba.size() * sizeof(float)),
            0);
}
