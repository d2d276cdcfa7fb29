// PSNR and SSIM against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <opencv2/core.hpp>

#include "image/image_metrics.h"
#include "util/hash.h"

using namespace pluvia;

namespace {

// A textured image in [lo, hi]: smooth ramps plus uniform noise, so SSIM has structure to see.
cv::Mat texture(int w, int h, int channels, float lo, float hi, uint64_t seed) {
  cv::Mat out(h, w, CV_32FC(channels));
  CounterRng rng(seed, 0);
  for (int y = 0; y < h; ++y) {
    float* row = out.ptr<float>(y);
    for (int x = 0; x < w; ++x) {
      for (int c = 0; c < channels; ++c) {
        const double smooth = 0.5 + 0.25 * std::sin(0.11 * x + 0.7 * c) * std::cos(0.07 * y);
        const double t = std::clamp(smooth + 0.25 * (rng.uniform() - 0.5), 0.0, 1.0);
        row[x * channels + c] = float(lo + (hi - lo) * t);
      }
    }
  }
  return out;
}

// The SSIM luminance term of two local means (contrast-structure term 1).
double luminanceTerm(double a, double b) {
  const double c1 = 0.01 * 0.01;
  return (2.0 * a * b + c1) / (a * a + b * b + c1);
}

}  // namespace

TEST(ImageMetrics, PsnrOfAKnownMeanSquaredError) {
  // Half the values off by d, half exact: MSE = d^2 / 2, PSNR = -10 log10(d^2 / 2).
  for (int channels : {1, 3}) {
    const cv::Mat truth = texture(64, 48, channels, 0.2f, 0.7f, 3);
    cv::Mat result = truth.clone();
    const float d = 0.05f;
    for (int y = 0; y < result.rows; ++y) {
      float* row = result.ptr<float>(y);
      for (int i = 0; i < result.cols * channels; ++i) row[i] += (i % 2 == 0) ? d : 0.0f;
    }
    // The float sums of truth + d are not exactly d apart: compute the expected MSE from them.
    double mse = 0.0;
    for (int y = 0; y < result.rows; ++y) {
      for (int i = 0; i < result.cols * channels; ++i) {
        const double e = double(result.ptr<float>(y)[i]) - double(truth.ptr<float>(y)[i]);
        mse += e * e;
      }
    }
    mse /= double(result.total() * size_t(channels));
    EXPECT_NEAR(mse, d * d / 2.0, 1e-8);
    EXPECT_NEAR(psnrDb(result, truth), -10.0 * std::log10(mse), 1e-9);
    EXPECT_NEAR(psnrDb(result, truth), -10.0 * std::log10(0.05 * 0.05 / 2.0), 1e-4);
  }
  // A constant offset of 0.1 everywhere: exactly 20 dB (up to float rounding of the inputs).
  const cv::Mat a(10, 10, CV_32FC3, cv::Scalar(0.25f, 0.25f, 0.25f));
  const cv::Mat b(10, 10, CV_32FC3, cv::Scalar(0.375f, 0.375f, 0.375f));  // offset 1/8 exactly
  EXPECT_NEAR(psnrDb(a, b), -20.0 * std::log10(0.125), 1e-12);
  EXPECT_EQ(psnrDb(a, a), std::numeric_limits<double>::infinity());
  EXPECT_THROW(psnrDb(a, cv::Mat(9, 10, CV_32FC3)), std::invalid_argument);
}

TEST(ImageMetrics, SsimOfIdenticalImagesIsOne) {
  for (int channels : {1, 3}) {
    const cv::Mat image = texture(80, 60, channels, 0.0f, 1.0f, 5);
    EXPECT_NEAR(ssim(image, image), 1.0, 1e-12);
  }
  // Even a flat image (no structure: the constants C1, C2 keep it defined).
  const cv::Mat flat(30, 30, CV_32FC3, cv::Scalar(0.4f, 0.4f, 0.4f));
  EXPECT_NEAR(ssim(flat, flat), 1.0, 1e-12);
}

TEST(ImageMetrics, SsimDropsAsNoiseGrows) {
  const cv::Mat truth = texture(96, 72, 3, 0.1f, 0.9f, 7);
  double previous = 1.0;
  for (double sigma : {0.005, 0.02, 0.05, 0.1, 0.2}) {
    cv::Mat noisy = truth.clone();
    cv::Mat noise(truth.size(), truth.type());
    cv::theRNG().state = 12345;
    cv::randn(noise, cv::Scalar::all(0.0), cv::Scalar::all(sigma));
    noisy += noise;
    const double s = ssim(noisy, truth);
    EXPECT_LT(s, previous) << "sigma " << sigma;
    EXPECT_GT(s, 0.0) << "sigma " << sigma;
    previous = s;
  }
  EXPECT_LT(previous, 0.8);
  // SSIM is symmetric in its arguments.
  cv::Mat noisy = truth + cv::Scalar::all(0.03);
  EXPECT_NEAR(ssim(noisy, truth), ssim(truth, noisy), 1e-12);
}

TEST(ImageMetrics, SsimOfAConstantOffsetIsItsLuminanceTerm) {
  // Flat images a and a + c: every window has the same means and no variance, so SSIM is the
  // luminance term (2 a (a + c) + C1) / (a^2 + (a + c)^2 + C1) exactly.
  for (float a : {0.05f, 0.3f, 0.8f}) {
    for (float c : {0.01f, 0.1f, -0.04f}) {
      const cv::Mat x(40, 50, CV_32FC3, cv::Scalar::all(a));
      const cv::Mat y(40, 50, CV_32FC3, cv::Scalar::all(a + c));
      EXPECT_NEAR(ssim(y, x), luminanceTerm(a, double(a + c)), 1e-9) << a << " + " << c;
    }
  }
  // A textured image plus a constant: the contrast-structure term stays 1 (y - x is constant, so
  // the variances and covariance agree), and the luminance term of every window lies between
  // its values at the image's darkest and brightest local mean.
  const float lo = 0.2f, hi = 0.6f, c = 0.15f;
  const cv::Mat x = texture(80, 64, 3, lo, hi, 11);
  const cv::Mat y = x + cv::Scalar::all(c);
  const double s = ssim(y, x);
  EXPECT_GE(s, luminanceTerm(lo, lo + c) - 1e-9);
  EXPECT_LE(s, luminanceTerm(hi, hi + c) + 1e-9);
  EXPECT_LT(s, 1.0);
}
