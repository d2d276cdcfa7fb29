// Stroke extraction (src/derain/stroke_extraction.h) on synthetic mattes whose streaks are
// known: where they are, how long, at which angle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "derain/stroke_extraction.h"

using namespace pluvia;
using derain::StrokeCollector;
using derain::StrokeExtractionSettings;

namespace {

struct Streak {
  double cx, cy;    // centre, pixels
  double lengthPx;  // of the segment
  double sigmaPx;   // Gaussian cross-section
  double peak;      // alpha on the axis
};

// Draws a streak at angleDeg (frame_stack.h convention: direction (sin a, -cos a)) into the
// matte, independently of the extraction: the alpha at a pixel is peak * exp(-d^2 / 2 sigma^2),
// d its distance to the segment.
void drawStreak(cv::Mat& matte, const Streak& s, double angleDeg) {
  const double a = angleDeg * M_PI / 180.0;
  const double dx = std::sin(a), dy = -std::cos(a);
  const int reach = int(std::ceil(s.lengthPx / 2 + 4 * s.sigmaPx)) + 1;
  for (int y = std::max(0, int(s.cy) - reach); y <= std::min(matte.rows - 1, int(s.cy) + reach);
       ++y)
    for (int x = std::max(0, int(s.cx) - reach); x <= std::min(matte.cols - 1, int(s.cx) + reach);
         ++x) {
      const double px = x - s.cx, py = y - s.cy;
      const double t = std::clamp(px * dx + py * dy, -s.lengthPx / 2, s.lengthPx / 2);
      const double ex = px - t * dx, ey = py - t * dy;
      const float value =
          float(s.peak * std::exp(-(ex * ex + ey * ey) / (2 * s.sigmaPx * s.sigmaPx)));
      matte.at<float>(y, x) = std::max(matte.at<float>(y, x), value);
    }
}

// Sensor noise as the solver leaves it: Gaussian, projected onto alpha >= 0.
cv::Mat noiseMatte(cv::Size size, double sigma, uint64_t seed) {
  cv::Mat noise(size, CV_32FC1);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, sigma);
  return cv::max(noise, 0.0f);
}

// Tilt of an atlas stroke's alpha-weighted principal axis from the vertical, degrees.
double strokeTiltDeg(const rain::StrokeLibrary& library, size_t i) {
  const auto& s = library.strokes[i];
  const cv::Mat atlas(library.atlas.height, library.atlas.width, CV_32FC1,
                      const_cast<float*>(library.atlas.alpha.data()));
  const cv::Moments m = cv::moments(atlas(cv::Rect(s.x, s.y, s.width, s.height)), false);
  return 0.5 * std::atan2(2.0 * m.mu11, m.mu02 - m.mu20) * 180.0 / M_PI;
}

}  // namespace

TEST(StrokeExtraction, FindsEveryStreakAtAnAngleWithItsLength) {
  for (double angle : {-25.0, 0.0, 12.0, 30.0}) {
    // Twelve streaks of lengths 24..68 px on a grid, well apart, in sensor noise.
    cv::Mat matte = noiseMatte({640, 480}, 0.01, 3);
    std::vector<double> lengths;
    for (int i = 0; i < 12; ++i) {
      const Streak s{80.0 + 160.0 * (i % 4), 90.0 + 150.0 * (i / 4), 24.0 + 4.0 * i, 0.8, 0.5};
      drawStreak(matte, s, angle);
      lengths.push_back(s.lengthPx);
    }
    StrokeCollector collector(StrokeExtractionSettings{});
    collector.addFrame(7, matte, angle, 0.01);
    const rain::StrokeLibrary library = collector.finish();
    ASSERT_EQ(library.strokes.size(), 12u) << "angle " << angle;
    EXPECT_EQ(collector.candidateCount(), 12u);

    std::vector<double> found;
    for (size_t i = 0; i < library.strokes.size(); ++i) {
      const auto& s = library.strokes[i];
      found.push_back(s.lengthPx);
      EXPECT_EQ(s.sourceFrame, 7);
      EXPECT_NEAR(s.contrast, 0.5, 0.1) << "angle " << angle;
      EXPECT_GT(s.widthPx, 1.0);
      EXPECT_LT(s.widthPx, 4.0);
      // Upright in the atlas: the rotation went the right way.
      EXPECT_LT(std::abs(strokeTiltDeg(library, i)), 2.0) << "angle " << angle << " stroke " << i;
      EXPECT_GT(s.height, 3 * s.width / 2);
    }
    std::sort(found.begin(), found.end());
    for (size_t i = 0; i < lengths.size(); ++i) {
      EXPECT_NEAR(found[i], lengths[i], 0.15 * lengths[i]) << "angle " << angle;
    }
  }
}

TEST(StrokeExtraction, AFaintStreakBrokenIntoDashesIsCutWhole) {
  // A faint streak as the solve's noise dead zone leaves it: dashes of 5 px, 3 px apart (rb2,
  // heavy rain filmed from a moving car). It is one streak of its full length, not nothing.
  for (double angle : {0.0, -37.0}) {
    cv::Mat matte = noiseMatte({320, 240}, 0.01, 21);
    cv::Mat streak = cv::Mat::zeros(matte.size(), CV_32FC1);
    drawStreak(streak, {160, 120, 48, 0.8, 0.15}, angle);
    const cv::Vec2d d(std::sin(angle * M_PI / 180.0), -std::cos(angle * M_PI / 180.0));
    for (int y = 0; y < streak.rows; ++y)
      for (int x = 0; x < streak.cols; ++x) {
        const double along = (x - 160) * d[0] + (y - 120) * d[1] + 24.0;  // 0 at one end
        if (std::fmod(along + 80.0, 8.0) >= 5.0) streak.at<float>(y, x) = 0.0f;
      }
    matte = cv::max(matte, streak);
    StrokeCollector collector(StrokeExtractionSettings{});
    collector.addFrame(0, matte, angle, 0.01);
    const rain::StrokeLibrary library = collector.finish();
    ASSERT_EQ(library.strokes.size(), 1u) << "angle " << angle;
    EXPECT_NEAR(library.strokes[0].lengthPx, 48.0, 0.2 * 48.0) << "angle " << angle;
  }
}

TEST(StrokeExtraction, RainAtAnotherAngleThanTheEstimateIsNoStroke) {
  // Streaks 40 degrees off the rain direction given: not rain strokes of this footage.
  cv::Mat matte = noiseMatte({320, 240}, 0.01, 4);
  drawStreak(matte, {160, 120, 50, 0.8, 0.5}, 40.0);
  StrokeCollector collector(StrokeExtractionSettings{});
  collector.addFrame(0, matte, 0.0, 0.01);
  EXPECT_EQ(collector.finish().strokes.size(), 0u);
}

TEST(StrokeExtraction, PureNoiseYieldsNoStrokes) {
  StrokeCollector collector(StrokeExtractionSettings{});
  for (int frame = 0; frame < 20; ++frame) {
    // White noise, with the solve's noise level and with none reported...
    collector.addFrame(frame, noiseMatte({320, 240}, 0.02, 100 + frame), 8.0, 0.02);
    collector.addFrame(frame, noiseMatte({320, 240}, 0.02, 200 + frame), 8.0, 0.0);
    // ...and noise smoothed along the rain, as Eq. (1)'s mu term leaves it: streaky by itself.
    cv::Mat smooth = noiseMatte({320, 240}, 0.05, 300 + frame), along;
    cv::GaussianBlur(smooth, along, cv::Size(1, 31), 0.0, 5.0);
    collector.addFrame(frame, along, 0.0, 0.0);
  }
  const rain::StrokeLibrary library = collector.finish();
  EXPECT_EQ(collector.candidateCount(), 0u);
  EXPECT_TRUE(library.strokes.empty());
  EXPECT_TRUE(library.atlas.rects.empty());
}

TEST(StrokeExtraction, StreaksClippedByTheFrameEdgeAreRejected) {
  const StrokeExtractionSettings settings;
  auto strokesIn = [&](const cv::Mat& matte, double angle, const cv::Mat& valid = cv::Mat()) {
    StrokeCollector collector(settings);
    collector.addFrame(0, matte, angle, 0.01, cv::Mat(), valid);
    return collector.finish().strokes.size();
  };
  const cv::Size size(320, 240);
  // Vertical rain: a streak running off the top, one off the left side, one inside, each alone
  // on a matte of its own noise.
  auto strokesOfOne = [&](int noiseSeed, const Streak& streak, const cv::Mat& valid = cv::Mat()) {
    cv::Mat matte = noiseMatte(size, 0.01, noiseSeed);
    drawStreak(matte, streak, 0.0);
    return strokesIn(matte, 0.0, valid);
  };
  EXPECT_EQ(strokesOfOne(5, {100, 10, 40, 0.8, 0.5}), 0u);
  EXPECT_EQ(strokesOfOne(6, {0.5, 120, 40, 0.8, 0.5}), 0u);
  EXPECT_EQ(strokesOfOne(7, {100, 120, 40, 0.8, 0.5}), 1u);

  // Slanted rain: the rotated frame's border is the edge. A streak whose lower end runs into
  // the bottom edge at 30 degrees.
  cv::Mat slanted = noiseMatte(size, 0.01, 8);
  drawStreak(slanted, {160, 232, 40, 0.8, 0.5}, 30.0);
  EXPECT_EQ(strokesIn(slanted, 30.0), 0u);
  drawStreak(slanted, {160, 120, 40, 0.8, 0.5}, 30.0);
  EXPECT_EQ(strokesIn(slanted, 30.0), 1u);

  // The edge of the valid area (a registered frame's reference area) counts as well.
  cv::Mat valid(size, CV_8UC1, cv::Scalar(255));
  valid(cv::Rect(0, 0, 100, 240)).setTo(0);
  cv::Mat clipped = noiseMatte(size, 0.01, 9);
  clipped(cv::Rect(0, 0, 100, 240)).setTo(0.0f);
  drawStreak(clipped, {100, 120, 40, 0.8, 0.5}, 0.0);
  clipped(cv::Rect(0, 0, 100, 240)).setTo(0.0f);
  EXPECT_EQ(strokesIn(clipped, 0.0, valid), 0u);
  EXPECT_EQ(strokesOfOne(7, {100, 120, 40, 0.8, 0.5}, valid), 0u);  // x = 100 is on that edge too
  EXPECT_EQ(strokesOfOne(10, {200, 120, 40, 0.8, 0.5}, valid), 1u);
}

TEST(StrokeExtraction, ShortAndRoundComponentsAreNoStrokes) {
  cv::Mat matte = noiseMatte({320, 240}, 0.01, 11);
  drawStreak(matte, {60, 60, 6, 0.8, 0.5}, 0.0);     // 8 px: too short
  drawStreak(matte, {160, 120, 14, 4.0, 0.5}, 0.0);  // long enough but about as wide as long
  StrokeCollector collector(StrokeExtractionSettings{});
  collector.addFrame(0, matte, 0.0, 0.01);
  EXPECT_TRUE(collector.finish().strokes.empty());
  EXPECT_EQ(collector.candidateCount(), 0u);
}

TEST(StrokeExtraction, RanksLongBrightIsolatedStreaksFirst) {
  cv::Mat matte = noiseMatte({480, 320}, 0.01, 12);
  const double angle = 10.0;
  drawStreak(matte, {100, 160, 18, 0.8, 0.12}, angle);  // short and faint
  drawStreak(matte, {380, 160, 60, 0.8, 0.6}, angle);   // long, bright, alone
  // As long and bright, but crowded by two others right beside it.
  drawStreak(matte, {240, 160, 60, 0.8, 0.6}, angle);
  drawStreak(matte, {247, 150, 40, 0.8, 0.5}, angle);
  drawStreak(matte, {233, 172, 40, 0.8, 0.5}, angle);
  StrokeCollector collector(StrokeExtractionSettings{});
  collector.addFrame(3, matte, angle, 0.01);
  const rain::StrokeLibrary library = collector.finish();
  ASSERT_GE(library.strokes.size(), 2u);
  EXPECT_NEAR(library.strokes.front().lengthPx, 60.0, 9.0);
  EXPECT_NEAR(library.strokes.front().contrast, 0.6, 0.1);
  // The short faint one is found, and ranked below the long bright isolated one.
  const auto faint = std::find_if(library.strokes.begin(), library.strokes.end(),
                                  [](const rain::StrokeInfo& s) { return s.contrast < 0.2; });
  ASSERT_NE(faint, library.strokes.end());
  EXPECT_LT(faint->score, library.strokes.front().score);
  for (size_t i = 1; i < library.strokes.size(); ++i)
    EXPECT_LE(library.strokes[i].score, library.strokes[i - 1].score);

  // The count keeps the best.
  StrokeExtractionSettings one;
  one.count = 1;
  StrokeCollector best(one);
  best.addFrame(3, matte, angle, 0.01);
  const rain::StrokeLibrary single = best.finish();
  ASSERT_EQ(single.strokes.size(), 1u);
  EXPECT_DOUBLE_EQ(single.strokes[0].score, library.strokes.front().score);
}

TEST(StrokeExtraction, AtlasIsPaddedAndAtMost1024Wide) {
  StrokeExtractionSettings settings;
  settings.count = 400;
  StrokeCollector collector(settings);
  // Rain at random places in every frame, streaks apart from each other.
  cv::RNG rng(5);
  for (int frame = 0; frame < 7; ++frame) {
    cv::Mat matte = noiseMatte({640, 480}, 0.01, 20 + frame);
    std::vector<cv::Rect> taken;
    for (int i = 0; i < 80;) {
      const Streak s{rng.uniform(20.0, 620.0), rng.uniform(35.0, 445.0),
                     20.0 + (i * 7 + frame) % 25, 0.7 + 0.05 * (i % 5), 0.3 + 0.005 * i};
      const cv::Rect box(int(s.cx) - 10, int(s.cy - s.lengthPx / 2) - 10, 20, int(s.lengthPx) + 20);
      if (std::any_of(taken.begin(), taken.end(),
                      [&](const cv::Rect& t) { return (t & box).area() > 0; }))
        continue;
      taken.push_back(box);
      drawStreak(matte, s, 0.0);
      ++i;
    }
    collector.addFrame(frame, matte, 0.0, 0.01);
  }
  const rain::StrokeLibrary library = collector.finish();
  ASSERT_EQ(library.strokes.size(), 400u);
  const auto& atlas = library.atlas;
  EXPECT_LE(atlas.width, 1024);
  ASSERT_EQ(atlas.alpha.size(), size_t(atlas.width) * atlas.height);
  ASSERT_EQ(atlas.rects.size(), library.strokes.size());
  // Every texel within 2 px of a rectangle but outside every rectangle is zero, and each
  // stroke's matte peaks at 1.
  std::vector<uint8_t> inRect(atlas.alpha.size(), 0);
  for (const auto& s : library.strokes)
    for (int y = s.y; y < s.y + s.height; ++y)
      for (int x = s.x; x < s.x + s.width; ++x) inRect[size_t(y) * atlas.width + x] = 1;
  for (size_t i = 0; i < library.strokes.size(); ++i) {
    const auto& s = library.strokes[i];
    EXPECT_EQ(atlas.rects[i][0], float(s.x));
    EXPECT_EQ(atlas.rects[i][3], float(s.y + s.height));
    ASSERT_GE(s.x, 2);
    ASSERT_GE(s.y, 2);
    ASSERT_LE(s.x + s.width + 2, atlas.width);
    ASSERT_LE(s.y + s.height + 2, atlas.height);
    float peak = 0.0f;
    for (int y = s.y - 2; y < s.y + s.height + 2; ++y)
      for (int x = s.x - 2; x < s.x + s.width + 2; ++x) {
        const size_t at = size_t(y) * atlas.width + x;
        if (!inRect[at]) {
          ASSERT_EQ(atlas.alpha[at], 0.0f) << "stroke " << i << " at " << x << "," << y;
        }
        const bool own = x >= s.x && x < s.x + s.width && y >= s.y && y < s.y + s.height;
        if (own) peak = std::max(peak, atlas.alpha[at]);
      }
    EXPECT_FLOAT_EQ(peak, 1.0f);
  }
}

TEST(StrokeExtraction, StaticLinesThatStayPutAreNoStrokes) {
  // Thin vertical lines of the scene leak into every frame's matte, moving as the camera pans;
  // one rain streak falls somewhere else in every frame.
  for (double pan : {0.0, 1.0, 7.0}) {
    StrokeCollector collector(StrokeExtractionSettings{});
    for (int frame = 0; frame < 5; ++frame) {
      cv::Mat matte = noiseMatte({320, 240}, 0.01, 40 + frame);
      for (int line = 0; line < 4; ++line)
        drawStreak(matte, {60.0 + 30.0 * line + pan * frame, 120, 60, 0.8, 0.4}, 0.0);
      drawStreak(matte, {220.0 + 15.0 * frame, 60.0 + 30.0 * frame, 30, 0.8, 0.5}, 0.0);
      collector.addFrame(frame, matte, 0.0, 0.01);
    }
    const rain::StrokeLibrary library = collector.finish();
    EXPECT_EQ(library.strokes.size(), 5u) << "pan " << pan;
    for (const auto& s : library.strokes) EXPECT_NEAR(s.lengthPx, 30.0, 4.5) << "pan " << pan;
  }
}

TEST(StrokeExtraction, StaticLinesUnderAFastPanAreNoStrokesGivenTheBackgrounds) {
  // The same lines under a pan of 24 px a frame (rb2's, from a vehicle): farther than mattes
  // alone can tell the camera's motion from rain falling, so the lines are only recognised as
  // static when the frames' backgrounds (a smooth texture panning with them) give the motion.
  const double pan = 24.0;
  cv::Mat scene(240, 320 + 5 * int(pan) + 64, CV_32FC1);
  cv::RNG(7).fill(scene, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::GaussianBlur(scene, scene, cv::Size(), 6.0);
  cv::normalize(scene, scene, 0.3, 0.5, cv::NORM_MINMAX);
  for (bool backgrounds : {false, true}) {
    StrokeCollector collector(StrokeExtractionSettings{});
    for (int frame = 0; frame < 5; ++frame) {
      cv::Mat matte = noiseMatte({320, 240}, 0.01, 40 + frame);
      for (int line = 0; line < 4; ++line)
        drawStreak(matte, {60.0 + 30.0 * line + pan * frame, 120, 60, 0.8, 0.4}, 0.0);
      drawStreak(matte, {290.0 - 15.0 * frame, 60.0 + 30.0 * frame, 30, 0.8, 0.5}, 0.0);
      // The scene moves right by `pan` a frame, as the lines do.
      const cv::Mat background = scene(cv::Rect(5 * int(pan) - int(pan) * frame, 0, 320, 240));
      collector.addFrame(frame, matte, 0.0, 0.01, backgrounds ? background.clone() : cv::Mat());
    }
    const rain::StrokeLibrary library = collector.finish();
    if (backgrounds) {
      EXPECT_EQ(library.strokes.size(), 5u);
      for (const auto& s : library.strokes) EXPECT_NEAR(s.lengthPx, 30.0, 4.5);
    } else {
      EXPECT_GT(library.strokes.size(), 5u) << "the mattes alone followed a 24 px pan";
    }
  }
}
