// The drawing order and batches of streak_batches.h: what both renderers composite by.
#include <gtest/gtest.h>

#include <cmath>

#include "gpu/streak_batches.h"

namespace pluvia::gpu {
namespace {

rain::StreakInstance streak(float widthPx, float angleDeg, float alpha = 0.5f, float tag = 0.0f) {
  const float radians = angleDeg * 3.14159265f / 180.0f;
  return {10.0f,
          10.0f,
          10.0f + 20.0f * std::cos(radians),
          10.0f + 20.0f * std::sin(radians),
          widthPx,
          alpha,
          tag,
          0.0f,
          0.0f,
          0.0f,
          1.0f,
          0.0f};
}

TEST(StreakBatches, LineWidthHoldsTheQuadAlongEitherAxis) {
  const float margin = 2.0f * kCoverageMarginPx;
  EXPECT_NEAR(lineWidthHolding(streak(2.0f, 90.0f)), 2.0f + margin, 1e-3f);  // vertical
  EXPECT_NEAR(lineWidthHolding(streak(2.0f, 0.0f)), 2.0f + margin, 1e-3f);   // horizontal
  // At 45 degrees the quad's cross-section along x (or y) is width * sqrt 2.
  EXPECT_NEAR(lineWidthHolding(streak(2.0f, 45.0f)), 2.0f * std::sqrt(2.0f) + margin, 1e-3f);
  // A still drop is a square: its axis is vertical.
  rain::StreakInstance still = streak(3.0f, 0.0f);
  still.tailX = still.headX, still.tailY = still.headY;
  EXPECT_NEAR(lineWidthHolding(still), 3.0f + margin, 1e-3f);
}

TEST(StreakBatches, NarrowClassesFirstInstanceOrderWithinAClass) {
  // Tags record the instance order; widths go wide, narrow, invisible, medium, narrow, huge.
  std::vector<rain::StreakInstance> streaks = {
      streak(5.0f, 80.0f, 0.5f, 0.0f),  streak(1.5f, 95.0f, 0.5f, 1.0f),
      streak(2.0f, 90.0f, 0.0f, 2.0f),  // alpha 0
      streak(2.5f, 85.0f, 0.5f, 3.0f),  streak(1.6f, 100.0f, 0.5f, 4.0f),
      streak(90.0f, 90.0f, 0.5f, 5.0f), streak(NAN, 90.0f, 0.5f, 6.0f)};
  const OrderedStreaks ordered = orderForDrawing(streaks);
  std::vector<float> tags;
  for (const auto& s : ordered.streaks) tags.push_back(s.depthMeters);
  EXPECT_EQ(tags, (std::vector<float>{1.0f, 4.0f, 3.0f, 0.0f, 5.0f}));

  // The batches tile the ordered streaks, widen strictly, and each line holds its streaks;
  // the streak wider than the widest line is drawn as triangles, last.
  size_t next = 0;
  float lastWidth = 0.0f;
  for (const StreakBatch& batch : ordered.batches) {
    EXPECT_EQ(batch.first, next);
    EXPECT_GT(batch.count, 0u);
    next += batch.count;
    if (batch.lineWidthPx == 0.0f) {
      EXPECT_EQ(&batch, &ordered.batches.back());
      continue;
    }
    EXPECT_GT(batch.lineWidthPx, lastWidth);
    EXPECT_EQ(batch.lineWidthPx, std::round(batch.lineWidthPx)) << "GL rounds line widths";
    lastWidth = batch.lineWidthPx;
    for (size_t i = batch.first; i < batch.first + batch.count; ++i) {
      EXPECT_GE(batch.lineWidthPx, lineWidthHolding(ordered.streaks[i]));
    }
  }
  EXPECT_EQ(next, ordered.streaks.size());
  ASSERT_FALSE(ordered.batches.empty());
  EXPECT_EQ(ordered.batches.back().lineWidthPx, 0.0f);
  EXPECT_EQ(ordered.batches.back().count, 1u);
}

}  // namespace
}  // namespace pluvia::gpu
