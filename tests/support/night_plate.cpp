#include "night_plate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "test_support.h"
#include "util/subprocess.h"

namespace pluvia::test {
namespace stdfs = std::filesystem;

namespace {

constexpr const char* kStreetMovie = "plate_static/opencv_vtest.avi";

// The distance from pixel centre (x + 0.5, y + 0.5) to the nearest of `points`.
double nearestPx(int x, int y, const std::vector<PixelXY>& points) {
  double nearest = 1e9;
  for (const PixelXY& p : points)
    nearest = std::min(nearest, std::hypot(x + 0.5 - p[0], y + 0.5 - p[1]));
  return nearest;
}

}  // namespace

Image lampInItsGlow(double coreRadiusPx) {
  Image lamp = flatImage(160, 120, 0.02f, 0.02f, 0.02f);
  for (int y = 0; y < lamp.height; ++y)
    for (int x = 0; x < lamp.width; ++x) {
      const double d = std::hypot(x + 0.5 - 80, y + 0.5 - 60);
      const float v =
          d <= coreRadiusPx
              ? 1.0f
              : std::max(0.02f, float(0.9 / (1.0 + std::pow((d - coreRadiusPx) / 15, 2))));
      std::fill(lamp.pixel(x, y), lamp.pixel(x, y) + 3, v);
    }
  return lamp;
}

bool haveStreetMovie() {
  return stdfs::exists(sharedData() / kStreetMovie);
}

std::string writeStreetPlate(const stdfs::path& dir, float gain,
                             const std::function<void(Image&)>& paintOver) {
  const stdfs::path still = dir / "street_still.png";
  const auto cut =
      runProcess({"ffmpeg", "-y", "-v", "error", "-i", (sharedData() / kStreetMovie).string(),
                  "-vf", "select=eq(n\\,2),scale=256:192", "-frames:v", "1", still.string()});
  if (cut.exitCode != 0)
    throw std::runtime_error("ffmpeg could not cut the street still: " + cut.output);
  const Image street = readImageFile(still);
  return writePlateSequence(dir, 1, 1, street.width, street.height, [&](Image& image, int) {
    for (size_t i = 0; i < image.rgba.size(); ++i)
      image.rgba[i] = (i % 4 == 3) ? 1.0f : gain * street.rgba[i];
    if (paintOver) paintOver(image);
  });
}

Image readAov(const stdfs::path& exr, const std::string& aov, const stdfs::path& dir) {
  const stdfs::path out = dir / (aov + "_only.exr");
  const auto r = runProcess({"oiiotool", exr.string(), "--ch",
                             "R=" + aov + ".R,G=" + aov + ".G,B=" + aov + ".B,A=" + aov + ".A",
                             "-o", out.string()});
  EXPECT_EQ(r.exitCode, 0) << r.output;
  return readImageFile(out);
}

NearFarRadiance streakRadianceNearFar(const Image& rain,
                                      const std::function<double(const float*)>& radiance,
                                      const std::vector<PixelXY>& nearTo, double nearPx,
                                      const std::vector<PixelXY>& farFrom, double farPx) {
  double nearSum = 0.0, farSum = 0.0;
  NearFarRadiance result;
  for (int y = 0; y < rain.height; ++y)
    for (int x = 0; x < rain.width; ++x) {
      const float* p = rain.pixel(x, y);
      if (p[3] < 0.02f) continue;
      if (nearestPx(x, y, nearTo) < nearPx) nearSum += radiance(p), ++result.nearCount;
      if (nearestPx(x, y, farFrom) > farPx) farSum += radiance(p), ++result.farCount;
    }
  result.nearMean = nearSum / result.nearCount;
  result.farMean = farSum / result.farCount;
  return result;
}

}  // namespace pluvia::test
