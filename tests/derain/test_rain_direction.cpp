// The rain angle from the mattes' spectrum: the convention (sign, fold), accuracy on drawn
// streaks, indifference to scene lines outside the searched range and to strong local ones.
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "derain/frame_stack.h"
#include "derain/rain_direction.h"

namespace pluvia::derain {
namespace {

// Anti-aliased streaks along `angleDeg` at random places (cv::line, independent of the estimator).
std::vector<cv::Mat> streakMattes(double angleDeg, int frames, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(0, 320), y(0, 240), length(15, 45);
  const cv::Vec2d d = streakDirection(angleDeg);
  std::vector<cv::Mat> mattes;
  for (int k = 0; k < frames; ++k) {
    cv::Mat matte = cv::Mat::zeros(240, 320, CV_32F);
    for (int s = 0; s < 120; ++s) {
      const double x0 = x(rng), y0 = y(rng), l = length(rng);
      // 4 fractional bits: endpoints at 1/16 pixel.
      cv::line(matte, cv::Point(int(x0 * 16), int(y0 * 16)),
               cv::Point(int((x0 + d[0] * l) * 16), int((y0 + d[1] * l) * 16)), cv::Scalar(0.3), 1,
               cv::LINE_AA, 4);
    }
    mattes.push_back(matte);
  }
  return mattes;
}

TEST(RainDirection, ConventionUpperEndToTheRightIsPositive) {
  const cv::Vec2d d = streakDirection(30.0);
  EXPECT_GT(d[0], 0.0);  // going up the streak (y decreasing) moves right
  EXPECT_LT(d[1], 0.0);
  EXPECT_DOUBLE_EQ(foldRainAngleDeg(-90.0), 90.0);
  EXPECT_DOUBLE_EQ(foldRainAngleDeg(150.0), -30.0);
  EXPECT_DOUBLE_EQ(foldRainAngleDeg(-30.0), -30.0);
}

TEST(RainDirection, FindsDrawnStreaksWithinHalfADegree) {
  for (double angle : {0.0, 7.0, -12.0, 25.0, -41.0, 55.0}) {
    const RainAngleEstimate e = estimateRainAngle(streakMattes(angle, 6, 7));
    EXPECT_NEAR(e.angleDeg, angle, 0.5) << "true angle " << angle;
    EXPECT_GT(e.salience, 2.0);
  }
}

TEST(RainDirection, HorizontalSceneLinesOutsideTheRangeDoNotWin) {
  std::vector<cv::Mat> mattes = streakMattes(-5.0, 6, 3);
  for (cv::Mat& m : mattes)  // strong, long horizontal lines (a railing's misregistered edge)
    for (int y = 20; y < 240; y += 40)
      cv::line(m, cv::Point(0, y), cv::Point(319, y), cv::Scalar(0.6), 1);
  EXPECT_NEAR(estimateRainAngle(mattes).angleDeg, -5.0, 1.0);
  // Searching every direction, the lines win: that is why the range exists.
  EXPECT_NEAR(std::abs(estimateRainAngle(mattes, 90.0).angleDeg), 90.0, 1.0);
}

TEST(RainDirection, RainOverTheFrameOutvotesStrongLinesInOneCorner) {
  // Faint rain at -37 deg everywhere, and in one corner the strong near-vertical lines a
  // pillar's misregistered edges leave in real mattes (rb2, a bus stop filmed from a moving
  // car): they hold more energy than all the rain, but only the tiles they lie in vote for them.
  std::vector<cv::Mat> mattes = streakMattes(-37.0, 6, 5);
  for (cv::Mat& m : mattes) {
    m *= 0.5;
    for (int x = 10; x < 90; x += 8)
      cv::line(m, cv::Point(x, 0), cv::Point(x + 4, 100), cv::Scalar(1.0), 2);
  }
  const RainAngleEstimate e = estimateRainAngle(mattes);
  EXPECT_NEAR(e.angleDeg, -37.0, 1.0);
  EXPECT_GT(e.agreement, 0.5);
}

TEST(RainDirection, NoStructureGivesVerticalWithSalienceOne) {
  const RainAngleEstimate e =
      estimateRainAngle({cv::Mat::zeros(64, 64, CV_32F), cv::Mat::zeros(64, 64, CV_32F)});
  EXPECT_EQ(e.angleDeg, 0.0);
  EXPECT_EQ(e.salience, 1.0);
  EXPECT_EQ(e.agreement, 0.0);
}

TEST(RainDirection, IsotropicNoiseHasLowSalience) {
  cv::Mat noise(240, 320, CV_32F);
  cv::randu(noise, 0.0, 1.0);
  const RainAngleEstimate e = estimateRainAngle({noise});
  EXPECT_LT(e.salience, 1.1);
  EXPECT_LT(e.agreement, 0.3);
}

}  // namespace
}  // namespace pluvia::derain
