// Whether a plate was shot in rain (src/derain/plate_rain.h): synthetic streaks falling over a
// still texture are found and a dry clip of the same texture is not; on real footage, NTURain's
// rain is found and the dry street plate with its walkers is not (skipped without
// ../shared/data).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "derain/plate_rain.h"
#include "io/clip_reader.h"
#include "test_support.h"
#include "util/error.h"

using namespace pluvia;
using namespace pluvia::derain;
using namespace pluvia::test;
namespace stdfs = std::filesystem;

namespace {

constexpr int kWidth = 640, kHeight = 360, kFrames = 9;

// A still, textured background (smoothed noise, codes 40-200) and, when `streaks`, bright
// vertical streaks 12 px long and 1.5 px wide at new places every frame.
std::vector<cv::Mat3f> syntheticClip(int streaksPerFrame) {
  std::mt19937 rng(7);
  cv::Mat1f noise(kHeight, kWidth);
  cv::randu(noise, 0.0f, 1.0f);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 3.0);
  cv::normalize(noise, noise, 40.0, 200.0, cv::NORM_MINMAX);
  cv::Mat3f background;
  cv::merge(std::vector<cv::Mat>{noise, noise * 0.9, noise * 0.8}, background);
  std::uniform_real_distribution<float> x(0.0f, float(kWidth)), y(0.0f, float(kHeight));
  std::vector<cv::Mat3f> frames;
  for (int f = 0; f < kFrames; ++f) {
    cv::Mat3f frame = background.clone();
    for (int s = 0; s < streaksPerFrame; ++s) {
      const cv::Point2f top(x(rng), y(rng));
      cv::Mat3f streak(frame.size(), cv::Vec3f(0, 0, 0));
      cv::line(streak, top, top + cv::Point2f(0.0f, 12.0f), cv::Scalar::all(35.0), 2, cv::LINE_AA);
      frame += streak;
    }
    frames.push_back(frame);
  }
  return frames;
}

std::vector<cv::Mat3f> readClip(const std::string& path, int first, int count) {
  std::unique_ptr<ClipReader> reader = openClip(path);
  const ClipInfo& info = reader->info();
  std::vector<cv::Mat3f> frames;
  for (int i = first; i < first + count && i < int(info.frames.size()); ++i) {
    const Image image = reader->read(info.frames[size_t(i)]);
    cv::Mat rgba(image.height, image.width, CV_32FC4, const_cast<float*>(image.rgba.data()));
    cv::Mat bgr, small;
    cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
    const double scale = 640.0 / image.width;
    cv::resize(bgr, small, cv::Size(640, int(std::lround(image.height * scale))), 0, 0,
               cv::INTER_AREA);
    frames.push_back(cv::Mat3f(small * 255.0));
  }
  return frames;
}

}  // namespace

TEST(PlateRain, SyntheticStreaksAreFoundAndAStillClipIsDry) {
  const PlateRain rained = measurePlateRain(syntheticClip(400));
  EXPECT_TRUE(rained.rained) << rained.summary();
  EXPECT_EQ(rained.frames, 3);
  // 400 streaks of about 2 x 12 px on 640 x 360: about 4 % of the frame, 1700 per Mpx.
  EXPECT_GT(rained.stats.coverage, 0.01) << rained.summary();
  EXPECT_GT(rained.stats.streaksPerMpx, 800.0) << rained.summary();
  EXPECT_NEAR(rained.stats.angleDeg, 0.0, 3.0) << rained.summary();

  const PlateRain dry = measurePlateRain(syntheticClip(0));
  EXPECT_FALSE(dry.rained) << dry.summary();
  EXPECT_LT(dry.stats.coverage, 0.0005) << dry.summary();
}

TEST(PlateRain, TooFewFramesAreRefused) {
  std::vector<cv::Mat3f> two = syntheticClip(0);
  two.resize(2);
  expectError([&] { measurePlateRain(two); }, "a clean plate needs 3 or more");
}

TEST(PlateRain, RealRainIsFoundAndADryStreetIsNot) {
  const stdfs::path data = sharedData();
  const stdfs::path nturain = data / "rain_real/nturain_ra1_real_rain_panning";
  const stdfs::path street = data / "plate_static/opencv_vtest.avi";
  if (!stdfs::exists(nturain / "00001.jpg") || !stdfs::exists(street))
    GTEST_SKIP() << "../shared/data is absent";
  const PlateRain rain = measurePlateRain(readClip((nturain / "%05d.jpg").string(), 0, kFrames));
  EXPECT_TRUE(rain.rained) << rain.summary();
  const PlateRain dry = measurePlateRain(readClip(street.string(), 100, kFrames));
  EXPECT_FALSE(dry.rained) << dry.summary();
}
