#include <gtest/gtest.h>

#include <fmt/format.h>

#include "pipeline/stage.h"
#include "stages/blur_settings.h"
#include "stages/registry.h"

using namespace pluvia;

namespace {

// A stage that only keeps what it was built with.
class KeepsSigma : public Stage {
 public:
  explicit KeepsSigma(double sigmaPx) : sigmaPx(sigmaPx) {}
  double sigmaPx;
};

Preset moderateWith(const std::vector<std::string>& sets) {
  return Preset::resolve("moderate", sets, presetSchema());
}

}  // namespace

// Every callback given gets the settings the section's function reads from the preset it is
// called with (not the defaults, not another preset's).
TEST(MakeStageInfo, CallbacksGetTheSettingsOfThePresetTheyAreCalledWith) {
  const StageInfo info = makeStageInfo(
      blurTable().section(), blurSettings,
      {.perClip = true,
       .noOpReason = [](const BlurSettings& blur,
                        const Preset&) { return fmt::format("sigma {:g}", blur.sigmaPx); },
       .cacheKey =
           [](const BlurSettings& blur, const Preset&, const ClipInfo& clip) {
             return fmt::format("{}@{:g}", clip.path, blur.sigmaPx);
           },
       .create = [](const BlurSettings& blur,
                    const Preset&) { return std::make_unique<KeepsSigma>(blur.sigmaPx); }});
  const Preset wide = moderateWith({"blur.sigma_px=7.5"});
  const Preset narrow = moderateWith({"blur.sigma_px=0.5"});
  EXPECT_EQ(info.spec.name, "blur");
  EXPECT_EQ(info.spec.params.size(), blurTable().section().params.size());
  EXPECT_TRUE(info.perClip);
  EXPECT_EQ(info.noOpReason(wide), "sigma 7.5");
  EXPECT_EQ(info.noOpReason(narrow), "sigma 0.5");
  ClipInfo clip;
  clip.path = "plate.mp4";
  EXPECT_EQ(info.cacheKey(narrow, clip), "plate.mp4@0.5");
  std::unique_ptr<Stage> stage = info.create(wide);
  auto* kept = dynamic_cast<KeepsSigma*>(stage.get());
  ASSERT_NE(kept, nullptr);
  EXPECT_EQ(kept->sigmaPx, 7.5);
}

// A callback not given stays empty: the planner then takes the section's declared inputs (reads),
// adds no note and caches nothing.
TEST(MakeStageInfo, CallbacksNotGivenStayEmpty) {
  const StageInfo info = makeStageInfo(blurTable().section(), blurSettings,
                                       {.create = [](const BlurSettings& blur, const Preset&) {
                                         return std::make_unique<KeepsSigma>(blur.sigmaPx);
                                       }});
  EXPECT_FALSE(info.perClip);
  EXPECT_FALSE(info.noOpReason);
  EXPECT_FALSE(info.note);
  EXPECT_FALSE(info.reads);
  EXPECT_FALSE(info.cacheKey);
  EXPECT_FALSE(info.frameMetadata);
  EXPECT_TRUE(info.create);
}
