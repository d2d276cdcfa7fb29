// The COLMAP tracking's cache key (stages/depth_tracking.h) follows what its result depends on:
// camera.lens_from_plate decides whether the plate's stated view starts COLMAP in place of
// camera.fov_deg, so turning it changes the key; a setting the tracking never reads does not.
#include <gtest/gtest.h>

#include "pipeline/camera_settings.h"
#include "preset/preset.h"
#include "stages/depth_settings.h"
#include "stages/depth_tracking.h"
#include "stages/registry.h"

using namespace pluvia;

namespace {

std::string keyWith(const std::vector<std::string>& sets, const ClipInfo& clip) {
  std::vector<std::string> all{"depth.source=colmap"};
  all.insert(all.end(), sets.begin(), sets.end());
  const Preset preset = Preset::resolve("moderate", all, presetSchema());
  return depthTrackingCacheKey(depthSettings(preset), cameraSettings(preset), clip);
}

}  // namespace

TEST(DepthTrackingKey, FollowsWhetherThePlatesLensIsTaken) {
  ClipInfo clip;
  clip.path = "plate.####.exr";
  clip.width = 1920;
  clip.height = 1280;
  clip.frames = {1, 2, 3};
  const std::string base = keyWith({}, clip);
  ASSERT_FALSE(base.empty());
  EXPECT_NE(keyWith({"camera.lens_from_plate=false"}, clip), base);
  EXPECT_EQ(keyWith({"rain.rate_mm_h=30"}, clip), base);
}
