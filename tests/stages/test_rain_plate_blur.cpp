// The rain softened to the plate's own blur (stages/rain_plate_blur.h): the blur it adds to the
// drawn streaks, and the layer blurred and composited over the plate again.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "stages/rain_plate_blur.h"
#include "util/error.h"

namespace pluvia {
namespace {

TEST(RainPlateBlur, AddsWhatTheDrawnStreaksLackInQuadrature) {
  // Drawn 1.5 px wide: a Gaussian of 1.5 / sqrt(2 pi) = 0.598 px.
  const double drawn = 1.5 / std::sqrt(2.0 * M_PI);
  EXPECT_NEAR(rainBlurBeyondDrawnPx(1.0, 1.5), std::sqrt(1.0 - drawn * drawn), 1e-12);
  EXPECT_EQ(rainBlurBeyondDrawnPx(0.5, 1.5), 0.0);  // a plate sharper than the drawn streaks
  EXPECT_EQ(rainBlurBeyondDrawnPx(0.0, 1.5), 0.0);  // blur not measured
}

// One pixel of rain (premultiplied 0.4 of light over 0.5 coverage) on a plate of two greys.
struct Frame {
  Image image{41, 41};
  std::vector<float> plate;
};

Frame oneDrop() {
  Frame f;
  for (int y = 0; y < 41; ++y)
    for (int x = 0; x < 41; ++x) {
      float* p = f.image.pixel(x, y);
      p[0] = p[1] = p[2] = x < 20 ? 0.2f : 0.6f;
    }
  f.plate = f.image.rgba;
  const size_t at = 20 * 41 + 20;
  for (const char* name : {"rain.R", "rain.G", "rain.B"}) f.image.plane(name)[at] = 0.4f;
  f.image.plane("rain.A")[at] = 0.5f;
  f.image.plane("matte")[at] = 0.5f;
  float* p = f.image.pixel(20, 20);
  for (int c = 0; c < 3; ++c) p[c] = 0.4f + 0.5f * f.plate[at * 4 + size_t(c)];
  return f;
}

TEST(RainPlateBlur, SpreadsTheLayerKeepingItsLightAndCompositesOverThePlate) {
  Frame f = oneDrop();
  constexpr double kSigmaPx = 1.2;
  blurRainOverPlate(f.image, f.plate, kSigmaPx);
  const std::vector<float>& rain = f.image.plane("rain.R");
  const std::vector<float>& coverage = f.image.plane("rain.A");
  double light = 0.0, covered = 0.0, spread = 0.0;
  for (int y = 0; y < 41; ++y)
    for (int x = 0; x < 41; ++x) {
      const size_t i = size_t(y) * 41 + size_t(x);
      light += rain[i];
      covered += coverage[i];
      spread += rain[i] * ((x - 20) * (x - 20));
      // rain + (1 - A) B with the plate under it, and the matte is the coverage.
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(f.image.rgba[i * 4 + size_t(c)],
                    f.image.plane(c == 0   ? "rain.R"
                                  : c == 1 ? "rain.G"
                                           : "rain.B")[i] +
                        (1.0f - coverage[i]) * f.plate[i * 4 + size_t(c)],
                    1e-6);
      EXPECT_EQ(f.image.plane("matte")[i], coverage[i]);
    }
  EXPECT_NEAR(light, 0.4, 1e-4);  // the layer's light is kept
  EXPECT_NEAR(covered, 0.5, 1e-4);
  // Its variance across is the blur's (sampled on whole pixels: within 5 %).
  EXPECT_NEAR(spread / light, kSigmaPx * kSigmaPx, 0.05 * kSigmaPx * kSigmaPx);
  // Far from the drop, the plate is kept exactly.
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(f.image.pixel(2, 2)[c], 0.2f);
    EXPECT_EQ(f.image.pixel(38, 38)[c], 0.6f);
  }
}

TEST(RainPlateBlur, NoBlurLeavesTheFrameAndAWrongPlateIsRefused) {
  Frame f = oneDrop();
  const std::vector<float> before = f.image.rgba;
  blurRainOverPlate(f.image, f.plate, 0.0);
  EXPECT_EQ(f.image.rgba, before);
  EXPECT_THROW(blurRainOverPlate(f.image, std::vector<float>(8, 0.0f), 1.0), Error);
}

}  // namespace
}  // namespace pluvia
