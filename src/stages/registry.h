#pragma once
// Every stage in pipeline order, and the full preset schema (stage sections plus the shared
// "camera" and "color" sections, pipeline/camera_settings.h and pipeline/color_settings.h). One
// table per section drives validation, planning and `pluvia describe`.
#include <vector>

#include "pipeline/stage.h"

namespace pluvia {

// derain, lighting, depth, darken, blur, fog, rainbow, lights, ripples, rain, splash, glare.
// Ripples lie on the ground, under the rain that falls in front of them. Darken, blur
// and fog act on the plate before the rain is composited: rain falls in front of the scene, so the
// scene's fog must not cover the drops (fog reaches the drops per drop instead, through their own
// depth). The rainbow and the lights' halos are light scattered by the whole rain volume along each
// ray, added to the plate like the fog. Glare comes last: the eye's veil covers everything in view.
const std::vector<StageInfo>& allStages();
const StageInfo* findStage(const std::string& name);

Schema presetSchema();

// Each stage's StageInfo (stages/<name>_stage.cpp); its section's table and settings are in
// stages/<section>_settings.h.
StageInfo derainStageInfo();
StageInfo lightingStageInfo();
StageInfo depthStageInfo();
StageInfo darkenStageInfo();
StageInfo blurStageInfo();
StageInfo fogStageInfo();
StageInfo lightsStageInfo();
StageInfo rainbowStageInfo();
StageInfo ripplesStageInfo();
StageInfo wetGroundStageInfo();
StageInfo rainStageInfo();
StageInfo splashStageInfo();
StageInfo glareStageInfo();

}  // namespace pluvia
