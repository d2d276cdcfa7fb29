// Skylight fog scatters the light of the rain as well as of the fog: it is a no-op only when
// there is neither, over the whole shot. A rain ramp that starts dry (no rain at frame 0) keeps
// it in the plan, and a shot without rain and without fog leaves it out.
#include <gtest/gtest.h>

#include "preset/preset.h"
#include "stages/registry.h"

using namespace pluvia;

namespace {

std::string fogNoOpReason(const std::vector<std::string>& sets) {
  const Preset preset = Preset::resolve("base", sets, presetSchema());
  for (const StageInfo& info : allStages())
    if (info.spec.name == "fog") return info.noOpReason ? info.noOpReason(preset) : "";
  ADD_FAILURE() << "no fog stage";
  return "";
}

}  // namespace

TEST(FogPlan, SkylightFogRunsWhenRainStartsLaterInTheShot) {
  EXPECT_EQ(
      fogNoOpReason({"fog.model=skylight", "fog.density=0", "rain.rate_mm_h=[[0,0],[48,40]]"}), "");
  EXPECT_EQ(fogNoOpReason({"fog.model=skylight", "fog.density=0", "rain.rate_mm_h=0"}),
            "density is 0 and no rain");
  EXPECT_EQ(fogNoOpReason({"fog.model=skylight", "fog.density=0", "rain.enabled=false"}),
            "density is 0 and no rain");
}
