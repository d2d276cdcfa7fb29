// The forward-backward consistency test of dense flow (src/derain/dense_flow.h) on flows whose
// disagreement is known.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "derain/dense_flow.h"

using namespace pluvia::derain;

namespace {

// A uniform forward flow `f` and a backward flow that returns short of the start by `errorPx`
// along x: |f + b| = errorPx everywhere.
bool consistent(cv::Vec2f f, float errorPx, double tolerancePx, double relative) {
  const cv::Size size(64, 48);
  const cv::Mat2f forward(size, f);
  const cv::Mat2f backward(size, cv::Vec2f(-f[0] + errorPx, -f[1]));
  const cv::Mat1b out =
      forwardBackwardConsistent(forward, backward, landingPoints(forward), tolerancePx, relative);
  // The centre lands inside the image for every flow used here.
  return out(24, 32) == 255;
}

}  // namespace

TEST(DenseFlow, AnAbsoluteToleranceAloneHoldsEveryFlowToIt) {
  EXPECT_TRUE(consistent({0, 0}, 0.9f, 1.0, 0.0));
  EXPECT_FALSE(consistent({0, 0}, 1.1f, 1.0, 0.0));
  EXPECT_FALSE(consistent({20, 0}, 1.1f, 1.0, 0.0));
}

TEST(DenseFlow, TheRelativeToleranceGrowsWithTheFlowsLength) {
  // |f + b|^2 < 0.1^2 (|f|^2 + |b|^2) + 1 px^2. For f = (20, 0) and an error e along x,
  // |b| = 20 - e: e = 2.5 passes (6.25 < 4 + 3.06 + 1 = 8.06), e = 3 fails (9 > 7.89).
  EXPECT_TRUE(consistent({20, 0}, 2.5f, 1.0, 0.1));
  EXPECT_FALSE(consistent({20, 0}, 3.0f, 1.0, 0.1));
  // A short flow keeps nearly the absolute tolerance: f = (1, 0) allows 1.005 px.
  EXPECT_FALSE(consistent({1, 0}, 1.1f, 1.0, 0.1));
  EXPECT_TRUE(consistent({1, 0}, 1.0f, 1.0, 0.1));
}
