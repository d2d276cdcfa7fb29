// The realism report's ground statistics (lab/ground_layer.h) on layers drawn by hand: round dots
// in the bottom third are counted with their area, brightness and lifetime; a long streak there,
// dots above the region and dots under the threshold are not.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "lab/ground_layer.h"

using namespace pluvia::lab;

namespace {

constexpr int kWidth = 300, kHeight = 300;  // the region: rows 200-299, 30000 px

// `dots` 3x3 dots of `codes` in the region's row 250, 20 px apart from x = `firstX`, plus a streak
// 1 px wide and 30 long, a dot above the region and a faint dot.
cv::Mat1f layer(int dots, int firstX, float codes) {
  cv::Mat1f l(kHeight, kWidth, 0.0f);
  for (int d = 0; d < dots; ++d) l(cv::Rect(firstX + 20 * d, 250, 3, 3)).setTo(codes);
  l(cv::Rect(10, 210, 1, 30)).setTo(40.0f);  // a streak: 30 times longer than wide
  l(cv::Rect(100, 50, 3, 3)).setTo(40.0f);   // above the ground
  l(cv::Rect(100, 280, 3, 3)).setTo(8.0f);   // under 10 codes
  return l;
}

}  // namespace

TEST(GroundLayer, CountsRoundBlobsOnTheGroundWithTheirAreaAndLight) {
  const GroundStats stats = measureGroundLayers({layer(6, 40, 30.0f), layer(6, 40, -30.0f)});
  EXPECT_NEAR(stats.blobsPerMpx, 6 * 1e6 / 30000.0, 1e-6);
  EXPECT_EQ(stats.areaP50Px, 9.0);
  EXPECT_FLOAT_EQ(stats.deltaP90, 30.0f) << "|dI|: a dark ring counts as a bright crown";
  EXPECT_EQ(stats.frames, 2);
}

TEST(GroundLayer, ABlobThatStaysLivesLongAndOneThatMovesOneFrame) {
  // The same dots in 4 frames: every later blob continues one, a life as long as the clip.
  const cv::Mat1f still = layer(5, 40, 20.0f);
  EXPECT_NEAR(measureGroundLayers({still, still, still, still}).lifetimeFrames, 4.0, 1e-9);
  // Dots that move 7 px each frame (more than kContinuePx): each lives one frame.
  EXPECT_NEAR(measureGroundLayers({layer(5, 40, 20.0f), layer(5, 47, 20.0f), layer(5, 54, 20.0f)})
                  .lifetimeFrames,
              1.0, 1e-9);
  // Half the dots stay: f = 1/2, a mean life of 2 frames.
  cv::Mat1f half = layer(0, 0, 0.0f);
  for (int d = 0; d < 4; ++d) half(cv::Rect(40 + 20 * d, 250, 3, 3)).setTo(20.0f);
  for (int d = 0; d < 4; ++d) half(cv::Rect(47 + 20 * d, 270, 3, 3)).setTo(20.0f);
  cv::Mat1f first = layer(0, 0, 0.0f);
  for (int d = 0; d < 4; ++d) first(cv::Rect(40 + 20 * d, 250, 3, 3)).setTo(20.0f);
  EXPECT_NEAR(measureGroundLayers({first, half}).lifetimeFrames, 2.0, 1e-9);
}
