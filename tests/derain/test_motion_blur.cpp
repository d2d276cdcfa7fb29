// The shutter measured from the plate's motion blur (derain/motion_blur.h), on synthetic clips
// filmed with a known shutter: textured blocks moving over a textured ground, each frame the mean
// of 32 instants over the open shutter, drawn at 4 times the size and reduced (a sensor's area
// sampling), then a lens's Gaussian blur and noise.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "derain/motion_blur.h"
#include "rain/drop_physics.h"

namespace pluvia::derain {
namespace {

constexpr int kWidth = 480, kHeight = 320, kSuper = 4;

struct Mover {
  cv::Mat1f texture;  // at kSuper times the size
  cv::Point2d startPx;
  cv::Point2d pxPerFrame;
};

// Random blocks of greys in linear light, at kSuper times the size.
cv::Mat1f blocks(int width, int height, int count, uint64_t seed) {
  cv::RNG rng(seed);
  cv::Mat1f texture(height * kSuper, width * kSuper, float(rng.uniform(0.1, 0.6)));
  for (int i = 0; i < count; ++i) {
    const int w = rng.uniform(6, 40) * kSuper, h = rng.uniform(6, 40) * kSuper;
    const int x = rng.uniform(-w / 2, width * kSuper), y = rng.uniform(-h / 2, height * kSuper);
    cv::rectangle(texture, cv::Rect(x, y, w, h), cv::Scalar(rng.uniform(0.03, 0.9)), cv::FILLED);
  }
  return texture;
}

// `texture` pasted at `originPx` (output px, rounded to the super grid) onto `canvas`.
void paste(cv::Mat1f& canvas, const cv::Mat1f& texture, cv::Point2d originPx) {
  const cv::Point origin(int(std::lround(originPx.x * kSuper)),
                         int(std::lround(originPx.y * kSuper)));
  const cv::Rect placed = cv::Rect(origin, texture.size()) & cv::Rect(cv::Point(), canvas.size());
  if (placed.empty()) return;
  texture(cv::Rect(placed.tl() - origin, placed.size())).copyTo(canvas(placed));
}

// Frames 0..count-1 of the ground panning at `panPxPerFrame` under the movers, the shutter open
// `shutterFraction` of each frame around its middle instant.
std::vector<cv::Mat1f> filmedClip(double shutterFraction, cv::Point2d panPxPerFrame,
                                  const std::vector<Mover>& movers, int count,
                                  double lensSigmaPx = 0.7) {
  const cv::Mat1f ground = blocks(kWidth + 160, kHeight + 160, 900, 7);
  cv::RNG noise(11);
  std::vector<cv::Mat1f> frames;
  constexpr int kInstants = 32;
  for (int frame = 0; frame < count; ++frame) {
    cv::Mat1f sum(kHeight * kSuper, kWidth * kSuper, 0.0f);
    for (int k = 0; k < kInstants; ++k) {
      const double t = frame + shutterFraction * ((k + 0.5) / kInstants - 0.5);
      cv::Mat1f canvas(sum.size(), 0.0f);
      paste(canvas, ground, cv::Point2d(-80, -80) + panPxPerFrame * t);
      for (const Mover& m : movers) paste(canvas, m.texture, m.startPx + m.pxPerFrame * t);
      sum += canvas;
    }
    sum /= double(kInstants);
    cv::Mat1f small;
    cv::resize(sum, small, cv::Size(kWidth, kHeight), 0, 0, cv::INTER_AREA);
    cv::GaussianBlur(small, small, cv::Size(0, 0), lensSigmaPx);
    cv::Mat1f grain(small.size());
    noise.fill(grain, cv::RNG::NORMAL, 0.0, 0.003);
    frames.push_back(small + grain);
  }
  return frames;
}

std::vector<Mover> walkers() {
  return {{blocks(130, 100, 60, 21), {40, 30}, {11, 0}},
          {blocks(110, 120, 60, 22), {300, 170}, {-9, -4}},
          {blocks(120, 90, 60, 23), {80, 200}, {7, -8}},
          {blocks(100, 100, 60, 24), {330, 20}, {-13, 6}}};
}

TEST(MotionBlur, WidthModelHasItsLimits) {
  // No ramp: a Gaussian edge's contrast over its steepest slope, sqrt(2 pi) sigma.
  EXPECT_NEAR(blurredEdgeWidthPx(0.0, 1.0), std::sqrt(2.0 * M_PI), 1e-9);
  // A ramp far longer than the blur is its own length.
  EXPECT_NEAR(blurredEdgeWidthPx(40.0, 0.5), 40.0, 1e-6);
  // Between, wider than either alone.
  EXPECT_GT(blurredEdgeWidthPx(2.0, 1.0), 2.0);
  EXPECT_GT(blurredEdgeWidthPx(2.0, 1.0), std::sqrt(2.0 * M_PI));
}

// Blocks crossing a still ground, as walkers cross a locked-off plate.
TEST(MotionBlur, FindsTheHalfOpenShutterOfWalkersOnAStillGround) {
  const ShutterFromBlur found = measureShutterFromBlur(filmedClip(0.5, {0, 0}, walkers(), 7));
  ASSERT_TRUE(found.measured) << found.summary;
  EXPECT_NEAR(found.shutterFraction, 0.5, 0.125) << found.summary;
}

TEST(MotionBlur, FindsAQuarterOpenShutter) {
  const ShutterFromBlur found = measureShutterFromBlur(filmedClip(0.25, {0, 0}, walkers(), 7));
  ASSERT_TRUE(found.measured) << found.summary;
  EXPECT_NEAR(found.shutterFraction, 0.25, 0.0625) << found.summary;
}

// NaN and infinite samples (a float plate's) are no edges, and the rest measures as before.
TEST(MotionBlur, NonFiniteSamplesAreLeftOut) {
  std::vector<cv::Mat1f> frames = filmedClip(0.5, {0, 0}, walkers(), 7);
  for (cv::Mat1f& f : frames) {
    f(10, 10) = std::numeric_limits<float>::quiet_NaN();
    f(200, 300) = std::numeric_limits<float>::infinity();
  }
  const ShutterFromBlur found = measureShutterFromBlur(frames);
  ASSERT_TRUE(found.measured) << found.summary;
  EXPECT_NEAR(found.shutterFraction, 0.5, 0.125) << found.summary;
}

// A pan moves every edge; the ones lying along the pan stay sharp and give the lens's blur.
TEST(MotionBlur, FindsTheShutterOfAPan) {
  const ShutterFromBlur found = measureShutterFromBlur(filmedClip(0.5, {9, 2}, {}, 7));
  ASSERT_TRUE(found.measured) << found.summary;
  EXPECT_NEAR(found.shutterFraction, 0.5, 0.125) << found.summary;
}

// A locked-off plate where nothing moves holds no measure of its shutter: it says so.
TEST(MotionBlur, AStillClipIsNotMeasured) {
  const ShutterFromBlur found = measureShutterFromBlur(filmedClip(0.5, {0, 0}, {}, 5));
  EXPECT_FALSE(found.measured);
  EXPECT_NE(found.summary.find("too little motion"), std::string::npos) << found.summary;
}

// The still edges' blur is the lens's and the pixel's (a box of 1 px: sigma^2 1/12) in
// quadrature, measured on a locked-off plate where nothing moves and on one with walkers, within
// 15 % from 0.76 px up; a sharper plate reads under the 0.6 px the rain is drawn with (so the
// rain is left as drawn there: stages/rain_plate_blur.h).
TEST(MotionBlur, AStillEdgesBlurIsMeasuredWithOrWithoutMotion) {
  for (const double lens : {0.7, 1.5}) {
    const double expected = std::sqrt(lens * lens + 1.0 / 12.0);
    const ShutterFromBlur still = measureShutterFromBlur(filmedClip(0.5, {0, 0}, {}, 5, lens));
    EXPECT_NEAR(still.stillBlurPx, expected, 0.15 * expected) << still.summary;
    const ShutterFromBlur walking =
        measureShutterFromBlur(filmedClip(0.5, {0, 0}, walkers(), 7, lens));
    EXPECT_NEAR(walking.stillBlurPx, expected, 0.15 * expected) << walking.summary;
  }
  const ShutterFromBlur sharp = measureShutterFromBlur(filmedClip(0.5, {0, 0}, {}, 5, 0.3));
  EXPECT_GT(sharp.stillBlurPx, 0.0) << sharp.summary;
  EXPECT_LT(sharp.stillBlurPx, 0.6) << sharp.summary;
}

// T = (L / W - 1) D / v: a streak as wide as long shows no motion; one 5 widths long, 4 drop
// passages of D / v = 1.5 mm / 5.4 m/s (Atlas's fall speed of a 1.5 mm drop).
TEST(MotionBlur, TheStreaksClockIsTheirLengthOverTheirWidth) {
  EXPECT_EQ(shutterFromStreaksSeconds(1.0), 0.0);
  EXPECT_EQ(shutterFromStreaksSeconds(0.0), 0.0);
  EXPECT_EQ(shutterFromStreaksSeconds(std::nan("")), 0.0);
  EXPECT_NEAR(shutterFromStreaksSeconds(5.0),
              4.0 * 1.5e-3 / rain::terminalVelocityMetersPerSecond(1.5), 1e-12);
  EXPECT_NEAR(shutterFromStreaksSeconds(5.0), 4.0 * 1.5e-3 / 5.4, 0.1 * 4.0 * 1.5e-3 / 5.4);
}

}  // namespace
}  // namespace pluvia::derain
