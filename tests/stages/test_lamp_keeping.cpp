// The grading stages leave a night plate's lamps as the plate holds them (stages/lamp_keeping.h):
// how much of each pixel a lamp holds (lampShare) on a synthetic lamp in its own glow, worked by
// hand, and a grade put back there and nowhere else.
#include <gtest/gtest.h>

#include <cmath>

#include "night_plate.h"
#include "stages/lamp_keeping.h"
#include "stages/plate_lights.h"
#include "test_support.h"

using namespace pluvia;

namespace {

// A 160 x 120 night plate (grey 0.02) with a clipped core of radius 6 px at (80, 60) in a glow
// 0.9 / (1 + ((d - 6) / 15)^2): over 0.3 (the glow mask) out to d = 6 + 15 sqrt(2) = 27.2 px.
// Its rings fall from about 0.93 at the core's edge (ring 6, part core) to 0.073 at 56 px (8 radii
// and 8 px), so nine tenths of that excess have faded where the glow is 0.159: d = 6 + 15
// sqrt(0.9 / 0.159 - 1) = 38.4 px, within a ring or two.
constexpr double kGlowReachPx = 38.4;
Image lampInItsGlow() {
  return test::lampInItsGlow(6.0);
}

float shareAt(const std::vector<float>& share, int x, int y) {
  return share[size_t(y) * 160 + size_t(x)];
}

}  // namespace

TEST(LampKeeping, ALampAndItsGlowAreKeptFeatheredOutsideThem) {
  const std::vector<float> share = lampShare(lampInItsGlow());
  ASSERT_EQ(share.size(), 160u * 120u);
  EXPECT_EQ(shareAt(share, 80, 60), 1.0f);       // the core
  EXPECT_EQ(shareAt(share, 80 + 20, 60), 1.0f);  // the glow mask, 0.50
  EXPECT_EQ(shareAt(share, 80, 60 - 34), 1.0f);  // the fainter glow, 0.19
  // Beyond the reach, feathered over as far again: a quarter of the way, three quarters kept
  // (within two rings' worth of the feather); nothing past twice the reach.
  const float most = shareAt(share, 80, 60 - int(1.25 * kGlowReachPx));
  EXPECT_GT(most, 0.7f);
  EXPECT_LT(most, 0.85f);
  EXPECT_EQ(shareAt(share, 80 + int(2.0 * kGlowReachPx) + 4, 60), 0.0f);
  EXPECT_EQ(shareAt(share, 5, 5), 0.0f);  // the dark corner
}

// A sunlit strip as bright far from its clipped patch as beside it is no lamp's glow: nothing of
// it is kept.
TEST(LampKeeping, ALitWallIsNoLamp) {
  Image wall = test::flatImage(160, 120, 0.02f, 0.02f, 0.02f);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 160; ++x)
      std::fill(wall.pixel(x, y), wall.pixel(x, y) + 3, x >= 70 && x < 130 && y < 8 ? 1.0f : 0.5f);
  for (float s : lampShare(wall)) ASSERT_EQ(s, 0.0f);
}

// A grade (everything to 0.8 of itself) put back where the lamp is: the core and the glow as the
// plate holds them, the dark plate graded, the feather between.
TEST(LampKeeping, AGradeIsPutBackWhereTheLampIs) {
  const Image plate = lampInItsGlow();
  const std::vector<float> share = lampShare(plate);
  Image graded = plate;
  const KeptLamps lamps(graded, share);
  for (size_t i = 0; i < graded.pixelCount(); ++i)
    for (int c = 0; c < 3; ++c) graded.rgba[i * 4 + size_t(c)] *= 0.8f;
  lamps.restore(graded);
  for (size_t i = 0; i < graded.pixelCount(); ++i) {
    const float before = plate.rgba[i * 4], after = graded.rgba[i * 4];
    ASSERT_NEAR(after, before * (0.8f + 0.2f * share[i]), 1e-6f) << i;
  }
  EXPECT_EQ(graded.pixel(80, 60)[0], 1.0f);
  EXPECT_FLOAT_EQ(graded.pixel(5, 5)[1], 0.8f * plate.pixel(5, 5)[1]);
  EXPECT_EQ(graded.pixel(5, 5)[3], 1.0f);  // alpha untouched
}
