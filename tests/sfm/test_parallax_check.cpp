// The parallax measurements before COLMAP (sfm/parallax_check.h) on frames of the synthetic
// street (lab/synthetic_scene.h): a walk shows parallax and its keyframes are spaced so that
// each pair of consecutive ones shows the wanted parallax; a tripod pan shows none.
#include <gtest/gtest.h>

#include <vector>

#include "image/image.h"
#include "lab/synthetic_scene.h"
#include "sfm/parallax_check.h"

namespace pluvia::sfm {
namespace {

constexpr int kWidth = 480, kHeight = 270;

std::vector<cv::Mat> renderFrames(const std::vector<lab::SyntheticPathKey>& keys) {
  lab::SyntheticSceneRenderer renderer(kWidth, kHeight);
  const lab::SyntheticView intrinsics = lab::defaultSyntheticIntrinsics(kWidth, kHeight);
  std::vector<cv::Mat> frames;
  for (const auto& key : keys)
    frames.push_back(rgbMat(renderer.render(lab::syntheticViewAt(intrinsics, key))));
  return frames;
}

TEST(ParallaxCheck, WalkHasParallaxAndKeyframesAreSpacedByIt) {
  const std::vector<cv::Mat> frames = renderFrames(lab::defaultSyntheticPath(48));
  const ParallaxProbe probe(frames);
  const ParallaxCheckSettings settings;
  const ParallaxCheck check = checkParallax(probe);
  EXPECT_EQ(check.verdict, ParallaxVerdict::Parallax) << check.parallaxFraction;
  // Neighbouring frames, 5 cm apart, show almost none: why frames are chosen at all.
  EXPECT_LT(probe.parallaxFraction(0, 1), settings.keyframeParallaxFraction);

  const std::vector<size_t> keys = selectKeyframes(probe);
  ASSERT_GE(keys.size(), 4u);
  EXPECT_EQ(keys.front(), 0u);
  EXPECT_EQ(keys.back(), 47u);
  EXPECT_LT(keys.size(), 24u);  // fewer than every other frame
  for (size_t k = 0; k + 2 < keys.size(); ++k) {
    EXPECT_LT(keys[k], keys[k + 1]);
    EXPECT_GE(probe.parallaxFraction(keys[k], keys[k + 1]), settings.keyframeParallaxFraction)
        << "keys " << keys[k] << " and " << keys[k + 1];
    // ... and the frame before the next key did not yet (the first frame that does is taken).
    if (keys[k + 1] > keys[k] + 1) {
      EXPECT_LT(probe.parallaxFraction(keys[k], keys[k + 1] - 1),
                settings.keyframeParallaxFraction);
    }
  }
}

TEST(ParallaxCheck, TripodPanHasNone) {
  std::vector<lab::SyntheticPathKey> keys(24, lab::defaultSyntheticPath(1)[0]);
  for (size_t i = 0; i < keys.size(); ++i) keys[i].yawDeg = -12.0 + double(i);
  const ParallaxCheck check = checkParallax(renderFrames(keys));
  EXPECT_EQ(check.verdict, ParallaxVerdict::NoParallax) << check.parallaxFraction;
  EXPECT_LT(check.parallaxFraction, ParallaxCheckSettings().minParallaxFraction);
  EXPECT_NE(check.message.find("pan or a tripod"), std::string::npos);
}

}  // namespace
}  // namespace pluvia::sfm
