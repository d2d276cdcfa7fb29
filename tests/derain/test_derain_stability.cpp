// Eq. (1) on the stiff and extreme cases: constant, black and white frames, no rain, lambda and
// mu over twelve decades, saturated rain, heavy noise, exactly 3 frames, non-finite pixels.
// Never NaN, alpha in [0, 1], and fewer than 3 frames is a clear error.
#include <cmath>

#include <gtest/gtest.h>

#include "derain/derain_solver.h"
#include "lab/synthetic_rain.h"
#include "util/error.h"

namespace pluvia::derain {
namespace {

void expectSane(const DerainResult& r, const std::string& what) {
  ASSERT_FALSE(r.background.empty()) << what;
  EXPECT_TRUE(cv::checkRange(r.background)) << what << ": S has NaN or Inf";
  for (const cv::Mat& a : r.alpha) {
    EXPECT_TRUE(cv::checkRange(a, true, nullptr, 0.0, 1.0 + 1e-6))
        << what << ": alpha outside [0, 1]";
  }
  for (const cv::Vec3f& c : r.rainColor)
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(std::isfinite(c[i]) && c[i] >= 0.0f) << what;
  EXPECT_TRUE(std::isfinite(r.angleDeg) && r.angleDeg > -90.0 && r.angleDeg <= 90.0) << what;
  EXPECT_TRUE(std::isfinite(r.residual)) << what;
  for (const DerainIteration& h : r.history) EXPECT_TRUE(std::isfinite(h.objective)) << what;
}

FrameStack constantStack(int frames, float value) {
  FrameStack stack;
  for (int k = 0; k < frames; ++k)
    stack.frames.push_back(cv::Mat(24, 32, CV_32FC3, cv::Scalar::all(value)));
  return stack;
}

cv::Mat texturedBackground() {
  cv::Mat background(48, 64, CV_32FC3);
  cv::randu(background, 0.05, 0.7);
  return background;
}

TEST(DerainStability, ConstantBlackAndWhiteFramesGiveNoRain) {
  for (float value : {0.0f, 0.5f, 1.0f}) {
    const DerainResult r = solveDerain(constantStack(6, value));
    expectSane(r, "constant " + std::to_string(value));
    for (const cv::Mat& a : r.alpha) EXPECT_EQ(cv::countNonZero(a), 0);
    EXPECT_LT(cv::norm(r.background - cv::Scalar::all(value), cv::NORM_INF), 1e-4);
  }
}

TEST(DerainStability, NoRainAtAllLeavesAlphaNearZero) {
  lab::SyntheticRainSettings noRain;
  noRain.frames = 10;
  noRain.streaksPerMegapixel = 0;
  noRain.noiseSigma = 0.02;
  const lab::SyntheticRain truth = lab::makeSyntheticRain(texturedBackground(), noRain);
  const DerainResult r = solveDerain(truth.stack);
  expectSane(r, "no rain");
  double meanAlpha = 0.0;
  for (const cv::Mat& a : r.alpha) meanAlpha += cv::mean(a)[0] / double(r.alpha.size());
  // Noise beyond three sigmas along C - S is all that can be taken for rain: a few pixels, faintly.
  EXPECT_LT(meanAlpha, 5e-4);
}

TEST(DerainStability, LambdaAndMuFromOneMillionthToOneMillion) {
  lab::SyntheticRainSettings rain;
  rain.frames = 4;
  const lab::SyntheticRain truth = lab::makeSyntheticRain(texturedBackground(), rain);
  for (double lambda : {1e-6, 1.0, 1e6})
    for (double mu : {1e-6, 1.0, 1e6}) {
      DerainSettings settings;
      settings.lambda = lambda;
      settings.mu = mu;
      settings.maxIterations = 3;
      expectSane(solveDerain(truth.stack, settings),
                 "lambda " + std::to_string(lambda) + " mu " + std::to_string(mu));
    }
}

TEST(DerainStability, SaturatedRainHeavyNoiseAndExactlyThreeFrames) {
  lab::SyntheticRainSettings saturated;
  saturated.frames = 3;
  saturated.minAlpha = 0.9;
  saturated.maxAlpha = 1.0;
  saturated.rainColor = {1.5f, 1.5f, 1.5f};  // clipped at 1 in the frames
  expectSane(solveDerain(lab::makeSyntheticRain(texturedBackground(), saturated).stack),
             "saturated, 3 frames");
  lab::SyntheticRainSettings noisy;
  noisy.frames = 5;
  noisy.noiseSigma = 0.2;
  expectSane(solveDerain(lab::makeSyntheticRain(texturedBackground(), noisy).stack), "heavy noise");
}

TEST(DerainStability, NonFinitePixelsAreIgnored) {
  lab::SyntheticRainSettings rain;
  rain.frames = 5;
  lab::SyntheticRain truth = lab::makeSyntheticRain(texturedBackground(), rain);
  truth.stack.frames[1].at<cv::Vec3f>(10, 10) = {NAN, 0.5f, INFINITY};
  truth.stack.frames[2].at<cv::Vec3f>(10, 10) = {-INFINITY, NAN, NAN};
  expectSane(solveDerain(truth.stack), "non-finite pixels");
}

TEST(DerainStability, FewerThanThreeFramesIsAClearError) {
  try {
    solveDerain(constantStack(2, 0.5f));
    FAIL() << "two frames were accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("at least 3 frames"), std::string::npos) << e.what();
  }
}

TEST(DerainStability, NegativeOrNaNWeightsAreRefused) {
  DerainSettings settings;
  settings.lambda = -1.0;
  EXPECT_THROW(solveDerain(constantStack(3, 0.5f), settings), Error);
  settings.lambda = 1.0;
  settings.mu = NAN;
  EXPECT_THROW(solveDerain(constantStack(3, 0.5f), settings), Error);
}

}  // namespace
}  // namespace pluvia::derain
