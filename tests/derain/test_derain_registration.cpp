// Derain decides registration from evidence: a locked-off camera is found by phase correlation
// before any feature is matched, and nothing is resampled (resampling a still clip cost 13 dB);
// a featureless still clip never fails for lack of features; a pan is still registered, and a
// frame of a pan that cannot be registered takes its neighbour's motion instead of aborting.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "derain/clip_derain.h"
#include "derain/derain_solver.h"
#include "derain/registration.h"
#include "lab/synthetic_rain.h"
#include "test_support.h"

namespace pluvia::derain {
namespace {

// A real photograph, display-encoded RGB 0..1, `width` pixels wide; empty without the data.
cv::Mat realBackground(int width) {
  const auto path = test::sharedData() / "sfm/opensfm_lund/03.jpg";
  if (test::sharedData().empty() || !std::filesystem::exists(path)) return {};
  cv::Mat bgr = cv::imread(path.string()), rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  cv::resize(rgb, rgb, cv::Size(width, width * rgb.rows / rgb.cols), 0, 0, cv::INTER_AREA);
  rgb.convertTo(rgb, CV_32FC3, 1.0 / 255.0);
  return rgb;
}

// A nearly featureless background: a smooth sky-like gradient (what made the old default stop
// with "8 matching features").
cv::Mat smoothBackground() {
  cv::Mat rgb(180, 320, CV_32FC3);
  for (int y = 0; y < rgb.rows; ++y)
    for (int x = 0; x < rgb.cols; ++x)
      rgb.at<cv::Vec3f>(y, x) =
          cv::Vec3f(0.5f + 0.2f * y / rgb.rows, 0.6f + 0.1f * x / rgb.cols, 0.8f);
  return rgb;
}

lab::SyntheticRain rainOver(const cv::Mat& background) {
  lab::SyntheticRainSettings rain;
  rain.frames = 20;
  rain.angleDeg = 8.0;
  rain.seed = 3;
  return lab::makeSyntheticRain(background, rain);
}

TEST(DerainRegistration, LockedOffClipIsFoundAndNotResampled) {
  const cv::Mat background = realBackground(320);
  if (background.empty()) GTEST_SKIP() << "../shared/data absent";
  const lab::SyntheticRain truth = rainOver(background);
  const Registration registration = registerFrames(truth.stack.frames, 10);
  EXPECT_TRUE(registration.lockedOff);
  EXPECT_FALSE(registration.moving());
  for (const auto& h : registration.referenceToFrame) EXPECT_EQ(h, cv::Matx33d::eye());
  // So the default solve is the --no-register solve, frame for frame.
  const FrameStack warped = warpToReference(truth.stack.frames, registration);
  for (size_t k = 0; k < warped.frames.size(); ++k)
    EXPECT_EQ(cv::norm(warped.frames[k], truth.stack.frames[k], cv::NORM_INF), 0.0);
  const double registered = cv::PSNR(solveDerain(warped).background, truth.background, 1.0);
  const double unregistered = cv::PSNR(solveDerain(truth.stack).background, truth.background, 1.0);
  EXPECT_NEAR(registered, unregistered, 1.0);
  EXPECT_GT(registered, cv::PSNR(temporalMedian(truth.stack), truth.background, 1.0));
}

TEST(DerainRegistration, FeaturelessStillClipNeverFails) {
  const lab::SyntheticRain truth = rainOver(smoothBackground());
  Registration registration;
  ASSERT_NO_THROW(registration = registerFrames(truth.stack.frames, 10));
  EXPECT_TRUE(registration.lockedOff);
  EXPECT_TRUE(registration.placedFrames.empty());
}

TEST(DerainRegistration, PanIsRegisteredAndBlankFramesTakeANeighboursMotion) {
  const cv::Mat background = realBackground(400);
  if (background.empty()) GTEST_SKIP() << "../shared/data absent";
  // A pan: each frame the view moves 1.5 px to the right (the scene 1.5 px left).
  std::vector<cv::Mat> frames;
  for (int k = 0; k < 9; ++k) {
    const cv::Matx23d shift(1, 0, -1.5 * k, 0, 1, 0);
    cv::Mat moved;
    cv::warpAffine(background, moved, shift, background.size(), cv::INTER_LINEAR,
                   cv::BORDER_REFLECT);
    frames.push_back(moved(cv::Rect(20, 0, 320, background.rows)).clone());
  }
  Registration pan;
  ASSERT_NO_THROW(pan = registerFrames(frames, 4));
  EXPECT_FALSE(pan.lockedOff);
  EXPECT_TRUE(pan.moving());
  EXPECT_NEAR(pan.referenceToFrame[8](0, 2), -6.0, 0.3);  // 4 frames after: 6 px
  // Frames 1 and 2 are blank (a flash, a lens cap): placed, not fatal.
  frames[1].setTo(cv::Scalar(0.5, 0.5, 0.5));
  frames[2].setTo(cv::Scalar(0.5, 0.5, 0.5));
  Registration gappy;
  ASSERT_NO_THROW(gappy = registerFrames(frames, 4));
  EXPECT_EQ(gappy.placedFrames, (std::vector<int>{1, 2}));
  // Frame 1 takes frame 0's motion and frame 2 frame 3's (the nearest registered).
  EXPECT_EQ(gappy.referenceToFrame[1], gappy.referenceToFrame[0]);
  EXPECT_EQ(gappy.referenceToFrame[2], gappy.referenceToFrame[3]);
}

}  // namespace
}  // namespace pluvia::derain

namespace pluvia::derain {
namespace {

double meanAbs(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  const cv::Scalar m = cv::mean(d);
  return (m[0] + m[1] + m[2]) / 3.0;
}

TEST(DerainClip, WindowsOverlapAndCrossFadeSoTheCleanPlateHasNoStep) {
  const cv::Mat background = realBackground(240);
  if (background.empty()) GTEST_SKIP() << "../shared/data absent";
  lab::SyntheticRainSettings rain;
  rain.frames = 20;
  rain.seed = 9;
  const lab::SyntheticRain truth = lab::makeSyntheticRain(background, rain);
  const auto dir = test::freshTempDir("derain_overlap");
  const std::string pattern = test::writePlateSequence(
      dir, 0, 19, background.cols, background.rows,
      [&](Image& image, int f) { image = imageFromMat(truth.stack.frames[size_t(f)]); });
  ClipDerainSettings settings;
  settings.window = 8;  // windows 0-7, 6-13, 12-19: frames 6-7 and 12-13 solved twice
  std::vector<cv::Mat> clean;
  derainClip(pattern, settings, [&](const ClipDerainFrame& f) { clean.push_back(f.clean); });
  ASSERT_EQ(clean.size(), 20u);
  // Locked off: one clean plate per window, the same on each of its own frames ...
  EXPECT_EQ(meanAbs(clean[4], clean[5]), 0.0);
  // ... and between two windows the step from frame 5 to frame 8 is spread over the overlap.
  const double step = meanAbs(clean[5], clean[8]);
  ASSERT_GT(step, 0.0);
  for (int k = 5; k < 8; ++k)
    EXPECT_LT(meanAbs(clean[size_t(k)], clean[size_t(k + 1)]), 0.7 * step);
}

}  // namespace
}  // namespace pluvia::derain
