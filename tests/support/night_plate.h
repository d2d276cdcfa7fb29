#pragma once
// The night-plate CLI tests' shared parts: a frame of the real street movie in ../shared/data
// dimmed to night, an AOV cut out of a render's EXR, and the streaks' radiance near the lamps
// against far from them.
#include <array>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "image/image.h"

namespace pluvia::test {

// A 160 x 120 night plate of grey 0.02 holding a lamp at (80, 60): a clipped core (1.0) of radius
// `coreRadiusPx` in a glow 0.9 / (1 + ((d - coreRadiusPx) / 15)^2), d the distance in px.
Image lampInItsGlow(double coreRadiusPx);

// Whether sharedData() has the street movie (plate_static/opencv_vtest.avi) the plate is cut from.
bool haveStreetMovie();

// Frame 2 of the street movie scaled to 256 x 192, its code values times `gain` (0.06: a night),
// alpha 1, with `paintOver` (when given) drawing on it, written as dir/plate.0001.png; returns
// the pattern "dir/plate.####.png". Call only when haveStreetMovie().
std::string writeStreetPlate(const std::filesystem::path& dir, float gain,
                             const std::function<void(Image&)>& paintOver = {});

// AOV `aov`'s four channels (aov.R, .G, .B, .A) of an EXR as an RGBA image; oiiotool cuts them
// out to dir/AOV_only.exr, and a failure to do so fails the test.
Image readAov(const std::filesystem::path& exr, const std::string& aov,
              const std::filesystem::path& dir);

// The streaks' mean radiance, `radiance(p)` over the rain AOV's pixels a streak covers
// (alpha >= 0.02), near the lamps (centre within `nearPx` of one of `nearTo`) and far from them
// (farther than `farPx` from all of `farFrom`); positions in pixels.
struct NearFarRadiance {
  double nearMean = 0.0, farMean = 0.0;
  int nearCount = 0, farCount = 0;
};
using PixelXY = std::array<double, 2>;
NearFarRadiance streakRadianceNearFar(const Image& rain,
                                      const std::function<double(const float*)>& radiance,
                                      const std::vector<PixelXY>& nearTo, double nearPx,
                                      const std::vector<PixelXY>& farFrom, double farPx);

}  // namespace pluvia::test
