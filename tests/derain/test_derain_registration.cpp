// Derain decides registration from evidence: a locked-off camera is found by phase correlation
// before any feature is matched, and nothing is resampled (resampling a still clip cost 13 dB);
// a featureless still clip never fails for lack of features; a pan is still registered, and a
// frame of a pan that cannot be registered takes its neighbour's motion instead of aborting; a
// camera moving past two depths (parallax) is followed by dense flow after the homography.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "derain/camera_speed.h"
#include "derain/clip_derain.h"
#include "derain/derain_solver.h"
#include "derain/registration.h"
#include "lab/parallax_clip.h"
#include "lab/real_rain_clip.h"
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
  EXPECT_EQ(gappy.placedWith, (std::vector<int>{0, 3}));
  // Frame 1 takes frame 0's motion and frame 2 frame 3's (the nearest registered).
  EXPECT_EQ(gappy.referenceToFrame[1], gappy.referenceToFrame[0]);
  EXPECT_EQ(gappy.referenceToFrame[2], gappy.referenceToFrame[3]);
}

// A façade of repeated windows (every 24 px across, 30 px down) with a little plaster texture:
// the texture whose periods fit a motion on a camera that never moved.
cv::Mat facadeOfWindows() {
  cv::Mat rgb(240, 320, CV_32FC3);
  cv::RNG rng(7);
  for (int y = 0; y < rgb.rows; ++y)
    for (int x = 0; x < rgb.cols; ++x) {
      const bool window = x % 24 >= 6 && x % 24 < 18 && y % 30 >= 6 && y % 30 < 24;
      const bool frame = !window && x % 24 >= 4 && x % 24 < 20 && y % 30 >= 4 && y % 30 < 26;
      const float plaster = 0.62f + 0.03f * float(rng.gaussian(1.0));
      const float value = window ? 0.18f : frame ? 0.85f : plaster;
      rgb.at<cv::Vec3f>(y, x) = cv::Vec3f(value, 0.95f * value, 0.9f * value);
    }
  return rgb;
}

TEST(DerainRegistration, AMotionThatExplainsLessThanNoneIsRejected) {
  // Locked-off windows in rain, and the 2.5 px shift a repeated texture can fit: the frames as
  // they are differ from the reference by the rain alone, the shifted ones by the windows' edges
  // too, so the shift is rejected and the solve is the --no-register solve.
  lab::SyntheticRainSettings settings;
  settings.frames = 20;
  settings.angleDeg = 12.0;
  settings.seed = 5;
  settings.streaksPerMegapixel = 8000;  // heavy rain: the temporal median keeps some of it
  const lab::SyntheticRain truth = lab::makeSyntheticRain(facadeOfWindows(), settings);
  const int reference = 10;
  Registration fitted;
  fitted.referenceToFrame.assign(20, cv::Matx33d::eye());
  for (int k = 0; k < 20; ++k)
    if (k != reference)
      fitted.referenceToFrame[size_t(k)] = cv::Matx33d(1, 0, 2.5, 0, 1, 0, 0, 0, 1);
  fitted.maxShiftPx = 2.5;
  ASSERT_TRUE(fitted.moving());
  keepMotionThatExplains(truth.stack.frames, reference, fitted);
  EXPECT_TRUE(fitted.motionRejected);
  EXPECT_FALSE(fitted.moving());
  EXPECT_GT(fitted.motionResidual, fitted.identityResidual);
  for (const auto& h : fitted.referenceToFrame) EXPECT_EQ(h, cv::Matx33d::eye());
  // The default registration of that clip: not moving either way (locked off or rejected), and
  // its solve is the --no-register one (within 1 dB), well over the temporal median (measured
  // +8.1 dB at this density).
  const Registration registration = registerFrames(truth.stack.frames, reference);
  EXPECT_FALSE(registration.moving());
  const double registered =
      cv::PSNR(solveDerain(warpToReference(truth.stack.frames, registration)).background,
               truth.background, 1.0);
  const double unregistered = cv::PSNR(solveDerain(truth.stack).background, truth.background, 1.0);
  EXPECT_NEAR(registered, unregistered, 1.0);
  EXPECT_GT(registered, cv::PSNR(temporalMedian(truth.stack), truth.background, 1.0) + 5.0);
}

TEST(DerainRegistration, AMotionThatExplainsThePanIsKept) {
  // The same façade panned 1.5 px a frame with its true homographies: the motion leaves far less
  // than the frames as they are.
  const cv::Mat wide = facadeOfWindows();
  std::vector<cv::Mat> frames;
  Registration pan;
  for (int k = 0; k < 9; ++k) {
    const cv::Matx23d shift(1, 0, -1.5 * k, 0, 1, 0);
    cv::Mat moved;
    cv::warpAffine(wide, moved, shift, wide.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
    frames.push_back(moved(cv::Rect(20, 0, 280, wide.rows)).clone());
    pan.referenceToFrame.push_back(cv::Matx33d(1, 0, -1.5 * (k - 4), 0, 1, 0, 0, 0, 1));
  }
  pan.maxShiftPx = 6.0;
  keepMotionThatExplains(frames, 4, pan);
  EXPECT_FALSE(pan.motionRejected);
  EXPECT_TRUE(pan.moving());
  EXPECT_LT(pan.motionResidual, 0.5 * pan.identityResidual);
}

}  // namespace
}  // namespace pluvia::derain

namespace pluvia::derain {
namespace {

// The Eq. (1) background of the frames registered onto frame `reference`.
cv::Mat solvedBackground(const std::vector<cv::Mat>& frames, const Registration& registration) {
  DerainSettings settings;
  if (registration.moving()) settings.registrationErrorPx = kResidualMisregistrationPx;
  return solveDerain(warpToReference(frames, registration), settings).background;
}

// The flow-registered temporal median of clean_plate.h, in the solver's values (RGB 0..1).
cv::Mat flowMedian(const std::vector<cv::Mat>& frames, int reference) {
  std::vector<cv::Mat3f> codes;
  for (const cv::Mat& frame : frames) codes.push_back(cv::Mat3f(frame * 255.0));
  return lab::cleanPlatesRgb(codes, {reference}).front().plate / 255.0;
}

// Pillars near the camera cross the frame 3.5 times as fast as the street behind them: the
// homography fits the street and ghosts the pillars; the dense refinement follows both.
TEST(DerainRegistration, ParallaxIsFollowedByDenseFlowNotGhosted) {
  const cv::Mat photo = realBackground(400);
  if (photo.empty()) GTEST_SKIP() << "../shared/data absent";
  const std::vector<cv::Mat> clean = lab::makeParallaxClip(photo, {320, 200});
  lab::SyntheticRainSettings rain;
  rain.frames = int(clean.size());
  rain.angleDeg = 8.0;
  rain.seed = 5;
  const lab::SyntheticRain truth = lab::makeSyntheticRainOver(clean, rain);
  const int reference = 4;
  const Registration homography = registerFrames(truth.stack.frames, reference, false);
  const Registration dense = registerFrames(truth.stack.frames, reference);
  ASSERT_TRUE(homography.moving());
  EXPECT_EQ(homography.denseFrames(), 0);
  EXPECT_GE(dense.denseFrames(), 6);
  EXPECT_LT(dense.flowResidual, 0.5 * dense.homographyResidual);
  const cv::Mat& answer = clean[size_t(reference)];
  const double homographyDb =
      cv::PSNR(solvedBackground(truth.stack.frames, homography), answer, 1.0);
  const double denseDb = cv::PSNR(solvedBackground(truth.stack.frames, dense), answer, 1.0);
  const double medianDb = cv::PSNR(flowMedian(truth.stack.frames, reference), answer, 1.0);
  const double inputDb = cv::PSNR(truth.stack.frames[size_t(reference)], answer, 1.0);
  // Measured: input 30.8, homography 14.2 (the pillars ghosted), dense 31.5, flow median 31.8.
  EXPECT_GT(denseDb, homographyDb + 10.0);
  EXPECT_GT(denseDb, medianDb - 1.5);
  EXPECT_GT(denseDb, inputDb);
}

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

TEST(DerainClip, AFastCameraGetsWindowsShortEnoughToRegister) {
  // The window keeps each end within a quarter of the frame's width of its middle frame.
  EXPECT_EQ(windowForCameraSpeed(20, 50.0, 640), 7);   // 3 x 50 px <= 160 px < 4 x 50 px
  EXPECT_EQ(windowForCameraSpeed(20, 1.6, 640), 20);   // a slow pan keeps the window
  EXPECT_EQ(windowForCameraSpeed(20, 0.0, 640), 20);   // a locked-off camera too
  EXPECT_EQ(windowForCameraSpeed(20, 900.0, 640), 3);  // never under 3 frames

  // A camera panning 15 px a frame over a 200 px wide crop of a real photograph (the houses and
  // the street), 12 frames: one window of all 12 would reach 90 px, nearly half the frame, from
  // its middle frame. (Further right the crop reaches a white wall with too few features.)
  const cv::Mat photo = realBackground(600);
  if (photo.empty()) GTEST_SKIP() << "../shared/data absent";
  const int width = 200, height = 150, stepPx = 15, frames = 12;
  const auto dir = test::freshTempDir("derain_fast_pan");
  const std::string pattern =
      test::writePlateSequence(dir, 0, frames - 1, width, height, [&](Image& image, int f) {
        image = imageFromMat(photo(cv::Rect(f * stepPx, 250, width, height)).clone());
      });
  ClipDerainSettings settings;  // the default window, 20 frames: all 12
  const ClipDerainSummary summary = derainClip(pattern, settings, [](const ClipDerainFrame&) {});
  ASSERT_FALSE(summary.windows.empty());
  for (const ClipDerainWindow& w : summary.windows) {
    // 7 frames at 15 px a frame (3 x 15 <= 50 < 4 x 15); measured 5, as the frame pairs'
    // homographies move a corner up to 20 px.
    EXPECT_LE(w.lastFrame - w.firstFrame + 1, 7);
    EXPECT_GE(w.lastFrame - w.firstFrame + 1, 5);
    EXPECT_NE(w.registration.find("motion"), std::string::npos)
        << "frames " << w.firstFrame << "-" << w.lastFrame << ": " << w.registration;
  }
}

}  // namespace
}  // namespace pluvia::derain
