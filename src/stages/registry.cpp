#include "stages/registry.h"

#include "pipeline/camera_settings.h"
#include "pipeline/color_settings.h"

namespace pluvia {

const std::vector<StageInfo>& allStages() {
  static const std::vector<StageInfo> stages{
      derainStageInfo(), lightingStageInfo(), depthStageInfo(), wetGroundStageInfo(),
      darkenStageInfo(), blurStageInfo(),     fogStageInfo(),   rainbowStageInfo(),
      lightsStageInfo(), ripplesStageInfo(),  rainStageInfo(),  splashStageInfo(),
      glareStageInfo()};
  return stages;
}

const StageInfo* findStage(const std::string& name) {
  for (const auto& s : allStages())
    if (s.spec.name == name) return &s;
  return nullptr;
}

Schema presetSchema() {
  Schema schema{cameraTable().section(), colorTable().section()};
  for (const auto& s : allStages()) schema.push_back(s.spec);
  return schema;
}

}  // namespace pluvia
