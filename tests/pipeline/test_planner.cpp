#include <gtest/gtest.h>

#include <set>

#include "pipeline/cache.h"
#include "pipeline/planner.h"
#include "stages/registry.h"
#include "test_support.h"

using namespace pluvia;

namespace {
ClipInfo fakeClipInfo() {
  ClipInfo clip;
  clip.path = "plate.####.exr";
  clip.frames = {1001, 1002};
  clip.width = 64;
  clip.height = 48;
  return clip;
}

const PlanEntry& entry(const Plan& plan, const std::string& stage) {
  for (const auto& e : plan.entries)
    if (e.stage == stage) return e;
  throw std::runtime_error("no stage " + stage);
}

Plan planWith(const std::vector<std::string>& sets, const ArtifactCache* cache = nullptr) {
  Preset preset = Preset::resolve("moderate", sets, presetSchema());
  return makePlan(preset, fakeClipInfo(), cache, "", allStages());
}
}  // namespace

TEST(Planner, ModerateRunsEverythingButDerain) {
  Plan plan = planWith({});
  for (const char* s : {"lighting", "depth", "darken", "blur", "fog", "rain", "write"})
    EXPECT_TRUE(plan.runs(s)) << s;
  EXPECT_FALSE(plan.runs("derain"));
  EXPECT_NE(entry(plan, "derain").reason.find("nothing reads its output"), std::string::npos);
}

TEST(Planner, NoOpParametersAreLeftOutWithReasons) {
  Plan plan = planWith({"fog.density=0", "blur.sigma_px=0", "darken.amount=0"});
  EXPECT_EQ(entry(plan, "fog").reason, "no-op: density is 0");
  EXPECT_EQ(entry(plan, "blur").reason, "no-op: sigma_px is 0");
  EXPECT_EQ(entry(plan, "darken").reason, "no-op: amount is 0");
  EXPECT_TRUE(plan.runs("rain"));
  EXPECT_TRUE(plan.runs("lighting"));  // the rain still reads it
}

TEST(Planner, RainRampingUpFromZeroIsNotANoOp) {
  // The first key is 0 mm/h, but the rain reaches 40: the stage must run.
  EXPECT_TRUE(planWith({"rain.rate_mm_h=[[0,0],[48,40]]"}).runs("rain"));
  Plan dry = planWith({"rain.rate_mm_h=[[0,0],[48,0]]"});
  EXPECT_FALSE(dry.runs("rain"));
  EXPECT_EQ(entry(dry, "rain").reason, "no-op: rate_mm_h is 0");
}

TEST(Planner, StagesWhoseOutputNobodyReadsAreLeftOut) {
  // No rain and a constant fog colour: nothing reads the environment; depth still feeds fog.
  Plan plan = planWith({"rain.rate_mm_h=0", "fog.color_source=constant"});
  EXPECT_FALSE(plan.runs("rain"));
  EXPECT_FALSE(plan.runs("lighting"));
  EXPECT_NE(entry(plan, "lighting").reason.find("nothing reads its output (environment)"),
            std::string::npos);
  EXPECT_TRUE(plan.runs("depth"));
  // Darken and blur grade by depth (moderate has both): with no fog, depth still feeds them ...
  EXPECT_TRUE(planWith({"rain.rate_mm_h=0", "fog.density=0"}).runs("depth"));
  // ... and when they grade every pixel alike, depth goes too.
  Plan bare =
      planWith({"rain.rate_mm_h=0", "fog.density=0", "darken.distance_m=0", "blur.distance_m=0"});
  EXPECT_FALSE(bare.runs("depth"));
  EXPECT_FALSE(bare.runs("lighting"));
}

TEST(Planner, DisabledStagesAndDerainOnDemand) {
  Plan plan = planWith({"rain.enabled=false"});
  EXPECT_EQ(entry(plan, "rain").reason, "disabled (rain.enabled = false)");
  Plan derain = planWith({"rain.strokes=derain"});
  EXPECT_TRUE(derain.runs("derain"));
}

TEST(Planner, CachedPerClipResultIsNotRecomputed) {
  auto dir = test::freshTempDir("planner_cache");
  ArtifactCache cache(dir);
  Preset preset = Preset::resolve("moderate", {}, presetSchema());
  const StageInfo* lighting = findStage("lighting");
  std::string key = lighting->cacheKey(preset, fakeClipInfo());
  EXPECT_TRUE(planWith({}, &cache).runs("lighting"));
  cache.store("lighting", key, {{"average_rgb", {0.1, 0.2, 0.3}}});
  Plan plan = planWith({}, &cache);
  EXPECT_FALSE(plan.runs("lighting"));
  EXPECT_TRUE(entry(plan, "lighting").cached);
  EXPECT_TRUE(plan.available("lighting"));
  // Other lighting parameters: another key, computed again.
  EXPECT_TRUE(planWith({"lighting.sample_frames=3"}, &cache).runs("lighting"));
}

// Every artifact a stage may read is made by an earlier stage or outside the stages, and what a
// stage reads and writes with given parameters is among what it declares.
TEST(Planner, EveryArtifactReadIsMadeBeforeItsReader) {
  std::set<std::string> made;
  for (const auto& [name, by] : artifactsMadeOutsideStages()) made.insert(name);
  const Preset preset = Preset::resolve("moderate", {"lights.find=on"}, presetSchema());
  for (const StageInfo& info : allStages()) {
    for (const auto& input : info.spec.inputs)
      EXPECT_TRUE(made.count(input)) << info.spec.name << " reads " << input << ", made by none";
    const std::set<std::string> inputs(info.spec.inputs.begin(), info.spec.inputs.end());
    const std::set<std::string> outputs(info.spec.outputs.begin(), info.spec.outputs.end());
    const auto reads = info.reads ? info.reads(preset) : info.spec.inputs;
    for (const auto& read : reads)
      EXPECT_TRUE(inputs.count(read)) << info.spec.name << " reads undeclared " << read;
    const auto writes = info.writes ? info.writes(preset) : info.spec.outputs;
    for (const auto& written : writes)
      EXPECT_TRUE(outputs.count(written)) << info.spec.name << " writes undeclared " << written;
    made.insert(info.spec.outputs.begin(), info.spec.outputs.end());
  }
}

// `plan` shows who makes and who reads each artifact: the frame's lights go from the lights
// stage to the rain and the glare, and COLMAP tracking makes depth the camera's second maker.
TEST(Planner, PlanShowsWhoMakesAndReadsEachArtifact) {
  auto find = [](const Plan& plan, const std::string& name) {
    for (const auto& a : plan.artifacts)
      if (a.name == name) return a;
    return PlanArtifact{};
  };
  const Plan plan = planWith({"lights.find=on"});
  const PlanArtifact lights = find(plan, "lights");
  EXPECT_EQ(lights.madeBy, std::vector<std::string>{"lights"});
  EXPECT_EQ(lights.readBy, (std::vector<std::string>{"rain", "glare"}));
  EXPECT_EQ(find(plan, "first_frame_depth").readBy, std::vector<std::string>{"lights"});
  EXPECT_EQ(find(plan, "camera").madeBy, std::vector<std::string>{"camera.path"});
  EXPECT_NE(plan.text().find("    lights             lights -> rain, glare\n"), std::string::npos)
      << plan.text();
  // Lit drops off: the rain no longer reads the lights.
  EXPECT_EQ(find(planWith({"lights.find=on", "lights.drops=false"}), "lights").readBy,
            std::vector<std::string>{"glare"});
  EXPECT_EQ(find(planWith({"depth.source=colmap"}), "camera").madeBy,
            (std::vector<std::string>{"camera.path", "depth"}));
  // A plate graded over its own rain on purpose: nothing asks whether it rained.
  EXPECT_EQ(find(planWith({"wet_ground.over_rain=true", "darken.over_rain=true",
                           "blur.over_rain=true", "fog.over_rain=true"}),
                 "plate_rain")
                .name,
            "");
}
