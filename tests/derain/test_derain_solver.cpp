// Eq. (1) on synthetic ground truth: real static images with rain of known matte, colour and
// direction composited over them (lab/synthetic_rain.h) and sensor noise. The targets of
// the issue: S at least 1 dB PSNR above the temporal median, the rain direction within 2 deg.
#include <gtest/gtest.h>
#include <Eigen/Dense>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "derain/derain_solver.h"
#include "lab/synthetic_rain.h"
#include "test_support.h"

namespace pluvia::derain {
namespace {

// A real photograph, display-encoded RGB 0..1, at `width` pixels wide.
cv::Mat realBackground(int width) {
  const auto path = test::sharedData() / "stitching/weir/weir_1.jpg";
  if (test::sharedData().empty() || !std::filesystem::exists(path)) return {};
  cv::Mat bgr = cv::imread(path.string());
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  cv::resize(rgb, rgb, cv::Size(width, width * rgb.rows / rgb.cols), 0, 0, cv::INTER_AREA);
  rgb.convertTo(rgb, CV_32FC3, 1.0 / 255.0);
  return rgb;
}

double meanAbsAlphaError(const std::vector<cv::Mat>& a, const std::vector<cv::Mat>& b) {
  double sum = 0.0;
  for (size_t k = 0; k < a.size(); ++k) sum += cv::mean(cv::abs(a[k] - b[k]))[0];
  return sum / double(a.size());
}

TEST(DerainSolver, BeatsTheMedianByOneDecibelAndFindsTheDirection) {
  const cv::Mat background = realBackground(320);
  if (background.empty()) GTEST_SKIP() << "../shared/data absent";
  for (double angle : {0.0, 12.0, -25.0}) {
    lab::SyntheticRainSettings rain;
    rain.frames = 20;
    rain.angleDeg = angle;
    rain.seed = 5;
    const lab::SyntheticRain truth = lab::makeSyntheticRain(background, rain);
    const double medianPsnr = cv::PSNR(temporalMedian(truth.stack), truth.background, 1.0);
    const DerainResult result = solveDerain(truth.stack);
    const double solverPsnr = cv::PSNR(result.background, truth.background, 1.0);
    EXPECT_GE(solverPsnr, medianPsnr + 1.0) << "angle " << angle;
    EXPECT_NEAR(result.angleDeg, angle, 2.0);
    EXPECT_TRUE(result.angleFound) << "angle " << angle;
    // The mattes: far closer to the truth than no rain at all is.
    std::vector<cv::Mat> none;
    for (const cv::Mat& a : truth.alpha) none.push_back(cv::Mat::zeros(a.size(), CV_32F));
    EXPECT_LT(meanAbsAlphaError(result.alpha, truth.alpha),
              0.4 * meanAbsAlphaError(none, truth.alpha));
    EXPECT_NEAR(result.noiseSigma, rain.noiseSigma, 0.3 * rain.noiseSigma);
  }
}

TEST(DerainSolver, ZeroIterationsIsTheMedianInitialisation) {
  cv::Mat background(24, 32, CV_32FC3, cv::Scalar(0.2, 0.4, 0.6));
  cv::randu(background, 0.1, 0.6);
  lab::SyntheticRainSettings rain;
  rain.frames = 5;
  const lab::SyntheticRain truth = lab::makeSyntheticRain(background, rain);
  DerainSettings settings;
  settings.maxIterations = 0;
  const DerainResult result = solveDerain(truth.stack, settings);
  EXPECT_EQ(cv::norm(result.background, temporalMedian(truth.stack), cv::NORM_INF), 0.0);
  EXPECT_EQ(result.iterations, 0);
  ASSERT_EQ(result.history.size(), 1u);
}

TEST(DerainSolver, IdenticalFramesGiveNoRainAndTheSmoothedBackground) {
  // Three identical frames I: alpha stays 0 (no rain direction is found), and S solves (3 + lambda
  // L) S = 3 I exactly, L the 4-neighbour graph Laplacian, checked here against a dense solve built
  // independently.
  const int w = 12, h = 9;
  cv::Mat frame(h, w, CV_32FC3);
  cv::randu(frame, 0.0, 1.0);
  FrameStack stack;
  stack.frames = {frame, frame.clone(), frame.clone()};
  DerainSettings settings;
  settings.cgTolerance = 1e-7;
  const DerainResult result = solveDerain(stack, settings);
  for (const cv::Mat& a : result.alpha) EXPECT_EQ(cv::countNonZero(a), 0);
  // No rain, no direction: D0 stays where it started, and says so.
  EXPECT_FALSE(result.angleFound);
  EXPECT_EQ(result.angleDeg, 0.0);
  Eigen::MatrixXd system = 3.0 * Eigen::MatrixXd::Identity(w * h, w * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (auto [nx, ny] : {std::pair{x + 1, y}, std::pair{x, y + 1}}) {
        if (nx >= w || ny >= h) continue;
        const int p = y * w + x, q = ny * w + nx;
        system(p, p) += settings.lambda, system(q, q) += settings.lambda;
        system(p, q) -= settings.lambda, system(q, p) -= settings.lambda;
      }
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd rhs(w * h);
    for (int p = 0; p < w * h; ++p) rhs[p] = 3.0 * frame.at<cv::Vec3f>(p / w, p % w)[c];
    const Eigen::VectorXd expected = system.llt().solve(rhs);
    for (int p = 0; p < w * h; ++p)
      EXPECT_NEAR(result.background.at<cv::Vec3f>(p / w, p % w)[c], expected[p], 1e-4);
  }
}

}  // namespace
}  // namespace pluvia::derain
