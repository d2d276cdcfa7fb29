// Synthetic rain, the ground truth of the derain report: the frames are exactly Eq. (1) of the
// returned mattes and colours, the streaks lie along the requested angle, and a seed gives the
// same rain every time.
#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "lab/synthetic_rain.h"

using namespace pluvia;
using namespace pluvia::lab;
using namespace pluvia::derain;

namespace {

// A smooth, coloured background in (0.1, 0.7).
cv::Mat background(int w, int h) {
  cv::Mat out(h, w, CV_32FC3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      out.at<cv::Vec3f>(y, x) = {float(0.1 + 0.6 * x / w), float(0.4 + 0.2 * std::sin(0.05 * y)),
                                 float(0.1 + 0.5 * y / h)};
    }
  }
  return out;
}

// The angle (frame_stack.h convention) of the principal axis of a mass distribution's second
// moments: (sxx, sxy, syy) about its centroid, x right, y down.
double principalAngleDeg(double sxx, double sxy, double syy) {
  const double theta = 0.5 * std::atan2(2.0 * sxy, sxx - syy);  // axis angle from +x, y down
  const double dx = std::cos(theta), dy = std::sin(theta);
  double a = std::atan2(dx, -dy) * 180.0 / M_PI;  // (sin a, -cos a) = (dx, dy)
  while (a > 90.0) a -= 180.0;
  while (a <= -90.0) a += 180.0;
  return a;
}

double angleDifferenceDeg(double a, double b) {
  double d = std::fmod(a - b, 180.0);
  if (d > 90.0) d -= 180.0;
  if (d < -90.0) d += 180.0;
  return std::abs(d);
}

struct Moments {
  double mass = 0, sxx = 0, sxy = 0, syy = 0;
};

// Second moments of each 8-connected blob of alpha > 0 about its own centroid, summed over the
// blobs that do not touch the border (those are cut, so not symmetric about their axis) and
// are one streak wide.
Moments blobMoments(const cv::Mat& alpha) {
  cv::Mat labels, stats, centroids;
  const cv::Mat mask = alpha > 0.0f;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  std::vector<double> m(size_t(n), 0.0), mx(size_t(n), 0.0), my(size_t(n), 0.0),
      mxx(size_t(n), 0.0), mxy(size_t(n), 0.0), myy(size_t(n), 0.0);
  for (int y = 0; y < alpha.rows; ++y) {
    for (int x = 0; x < alpha.cols; ++x) {
      const int l = labels.at<int>(y, x);
      if (l == 0) continue;
      const double a = alpha.at<float>(y, x);
      m[size_t(l)] += a;
      mx[size_t(l)] += a * x;
      my[size_t(l)] += a * y;
      mxx[size_t(l)] += a * x * x;
      mxy[size_t(l)] += a * x * y;
      myy[size_t(l)] += a * y * y;
    }
  }
  Moments total;
  for (int l = 1; l < n; ++l) {
    const int x = stats.at<int>(l, cv::CC_STAT_LEFT), y = stats.at<int>(l, cv::CC_STAT_TOP);
    const int w = stats.at<int>(l, cv::CC_STAT_WIDTH), h = stats.at<int>(l, cv::CC_STAT_HEIGHT);
    if (x == 0 || y == 0 || x + w == alpha.cols || y + h == alpha.rows) continue;
    const size_t i = size_t(l);
    const double cx = mx[i] / m[i], cy = my[i] / m[i];
    const double sxx = mxx[i] - m[i] * cx * cx, sxy = mxy[i] - m[i] * cx * cy,
                 syy = myy[i] - m[i] * cy * cy;
    // Two streaks side by side that touch make one blob as wide as their offset: its axis is
    // not theirs. One streak's variance across is at most about 0.6 px^2 (a 2.5 px core with
    // one-pixel soft edges), so a blob wider than that is skipped.
    const double minor = 0.5 * (sxx + syy - std::sqrt((sxx - syy) * (sxx - syy) + 4.0 * sxy * sxy));
    if (minor / m[i] > 1.0) continue;
    total.mass += m[i];
    total.sxx += sxx;
    total.sxy += sxy;
    total.syy += syy;
  }
  return total;
}

}  // namespace

TEST(SyntheticRain, FramesAreEquationOneOfTheTrueMattesAndColours) {
  SyntheticRainSettings settings;
  settings.frames = 4;
  settings.noiseSigma = 0.0;
  settings.seed = 42;
  const cv::Mat s = background(200, 150);
  const SyntheticRain rain = makeSyntheticRain(s, settings);
  ASSERT_EQ(rain.stack.frames.size(), 4u);
  ASSERT_EQ(rain.alpha.size(), 4u);
  ASSERT_EQ(rain.rainColor.size(), 4u);
  EXPECT_EQ(cv::norm(rain.background, s, cv::NORM_INF), 0.0);
  for (size_t k = 0; k < 4; ++k) {
    const cv::Mat& frame = rain.stack.frames[k];
    ASSERT_EQ(frame.type(), CV_32FC3);
    ASSERT_EQ(rain.alpha[k].type(), CV_32FC1);
    ASSERT_EQ(frame.size(), s.size());
    const cv::Vec3f c = rain.rainColor[k];
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_GE(c[ch], 0.97f * settings.rainColor[ch] - 1e-6f);
      EXPECT_LE(c[ch], 1.03f * settings.rainColor[ch] + 1e-6f);
    }
    int rainy = 0;
    double maxError = 0.0;
    for (int y = 0; y < frame.rows; ++y) {
      for (int x = 0; x < frame.cols; ++x) {
        const double a = rain.alpha[k].at<float>(y, x);
        ASSERT_GE(a, 0.0);
        ASSERT_LE(a, 1.0);
        if (a > 0.0) ++rainy;
        for (int ch = 0; ch < 3; ++ch) {
          const double expected = (1.0 - a) * s.at<cv::Vec3f>(y, x)[ch] + a * c[ch];
          // Background and colour are inside (0, 1): nothing clamps here.
          maxError = std::max(maxError, std::abs(frame.at<cv::Vec3f>(y, x)[ch] - expected));
        }
      }
    }
    EXPECT_LT(maxError, 1e-6) << "frame " << k;
    // 900 streaks per megapixel of 15-60 px by 1-2.5 px: a few percent of the pixels.
    EXPECT_GT(rainy, 0.01 * frame.total()) << "frame " << k;
    EXPECT_LT(rainy, 0.3 * frame.total()) << "frame " << k;
  }
  // Each frame has its own rain.
  EXPECT_GT(cv::norm(rain.alpha[0], rain.alpha[1], cv::NORM_L1), 1.0);
}

TEST(SyntheticRain, NoisyFramesAreClampedAndNoiseHasTheRequestedSigma) {
  SyntheticRainSettings settings;
  settings.frames = 2;
  settings.noiseSigma = 0.02;
  cv::Mat s = background(160, 120);
  s(cv::Rect(0, 0, 40, 40)).setTo(cv::Scalar::all(0.0));  // noise must be clamped here
  const SyntheticRain rain = makeSyntheticRain(s, settings);
  double sum = 0.0, sumSq = 0.0;
  long count = 0;
  for (size_t k = 0; k < 2; ++k) {
    double lo, hi;
    cv::minMaxLoc(rain.stack.frames[k].reshape(1), &lo, &hi);
    EXPECT_GE(lo, 0.0);
    EXPECT_LE(hi, 1.0);
    for (int y = 40; y < s.rows; ++y) {  // away from the clamped corner
      for (int x = 0; x < s.cols; ++x) {
        const double a = rain.alpha[k].at<float>(y, x);
        for (int ch = 0; ch < 3; ++ch) {
          const double e = rain.stack.frames[k].at<cv::Vec3f>(y, x)[ch] -
                           ((1.0 - a) * s.at<cv::Vec3f>(y, x)[ch] + a * rain.rainColor[k][ch]);
          sum += e;
          sumSq += e * e;
          ++count;
        }
      }
    }
  }
  const double mean = sum / count, sigma = std::sqrt(sumSq / count - mean * mean);
  EXPECT_NEAR(mean, 0.0, 5e-4);
  EXPECT_NEAR(sigma, 0.02, 0.02 * 0.03);
}

TEST(SyntheticRain, TheSameSeedGivesTheSameRainAndAnotherSeedOther) {
  SyntheticRainSettings settings;
  settings.frames = 3;
  settings.seed = 9;
  const cv::Mat s = background(120, 90);
  const SyntheticRain a = makeSyntheticRain(s, settings), b = makeSyntheticRain(s, settings);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(cv::norm(a.stack.frames[k], b.stack.frames[k], cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(a.alpha[k], b.alpha[k], cv::NORM_INF), 0.0);
    EXPECT_EQ(a.rainColor[k], b.rainColor[k]);
  }
  // A frame's rain does not depend on how many frames are made.
  settings.frames = 1;
  const SyntheticRain one = makeSyntheticRain(s, settings);
  EXPECT_EQ(cv::norm(one.stack.frames[0], a.stack.frames[0], cv::NORM_INF), 0.0);
  settings.frames = 3;
  settings.seed = 10;
  const SyntheticRain other = makeSyntheticRain(s, settings);
  EXPECT_GT(cv::norm(other.alpha[0], a.alpha[0], cv::NORM_L1), 1.0);
}

TEST(SyntheticRain, StreaksLieAlongTheRequestedAngle) {
  const cv::Mat s = background(320, 240);
  for (double angle : {0.0, 12.0, -25.0, 40.0, -63.0, 80.0, 90.0, 100.0}) {
    SyntheticRainSettings settings;
    settings.frames = 3;
    settings.angleDeg = angle;
    settings.noiseSigma = 0.0;
    settings.streaksPerMegapixel = 300;  // sparse: few blobs merge
    settings.seed = 3;
    const SyntheticRain rain = makeSyntheticRain(s, settings);
    const double folded = angle > 90.0 ? angle - 180.0 : angle;
    EXPECT_NEAR(rain.angleDeg, folded, 1e-12);
    for (size_t k = 0; k < rain.alpha.size(); ++k) {
      const Moments m = blobMoments(rain.alpha[k]);
      ASSERT_GT(m.mass, 0.0);
      const double measured = principalAngleDeg(m.sxx, m.sxy, m.syy);
      EXPECT_LT(angleDifferenceDeg(measured, angle), 1.0)
          << "requested " << angle << ", measured " << measured << ", frame " << k;
    }
  }
}

TEST(SyntheticRain, OneStreakAtATime) {
  // A single streak per frame, its moments over the whole frame: no blob segmentation involved.
  const cv::Mat s = background(256, 256);
  for (double angle : {7.0, -33.0, 80.0, 90.0, 100.0}) {
    SyntheticRainSettings settings;
    settings.frames = 12;
    settings.angleDeg = angle;
    settings.noiseSigma = 0.0;
    settings.streaksPerMegapixel = 1e6 / (256.0 * 256.0);  // exactly one
    settings.minLengthPx = 40;
    const SyntheticRain rain = makeSyntheticRain(s, settings);
    int measuredFrames = 0;
    for (const cv::Mat& alpha : rain.alpha) {
      const Moments m = blobMoments(alpha);  // zero when the streak touches the border
      if (m.mass == 0.0) continue;
      ++measuredFrames;
      EXPECT_LT(angleDifferenceDeg(principalAngleDeg(m.sxx, m.sxy, m.syy), angle), 1.0);
      // Brighter at the lower end (opacity ramps from 1/2 to 1 of its peak): along the streak
      // the alpha-weighted centroid lies 1/18 of its length below the middle.
      const double dx = std::sin(angle * M_PI / 180.0), dy = -std::cos(angle * M_PI / 180.0);
      double lo = 1e9, hi = -1e9, mass = 0.0, moment = 0.0;
      for (int y = 0; y < alpha.rows; ++y) {
        for (int x = 0; x < alpha.cols; ++x) {
          const double a = alpha.at<float>(y, x), u = x * dx + y * dy;  // u grows upward
          if (a <= 0.0) continue;
          lo = std::min(lo, u), hi = std::max(hi, u);
          mass += a, moment += a * u;
        }
      }
      EXPECT_LT(moment / mass, 0.5 * (lo + hi) - 0.03 * (hi - lo));
    }
    EXPECT_GE(measuredFrames, 4);
  }
}

TEST(SyntheticRain, RejectsBadInput) {
  SyntheticRainSettings settings;
  EXPECT_ANY_THROW(makeSyntheticRain(cv::Mat(), settings));
  EXPECT_ANY_THROW(makeSyntheticRain(cv::Mat(10, 10, CV_8UC3), settings));
  settings.frames = 0;
  EXPECT_ANY_THROW(makeSyntheticRain(background(10, 10), settings));
}
