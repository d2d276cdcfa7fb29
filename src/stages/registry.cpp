#include "stages/registry.h"

namespace pluvia {

const std::vector<StageInfo>& allStages() {
  static const std::vector<StageInfo> stages{derainStageInfo(), environmentStageInfo(), depthStageInfo(),
                                             darkenStageInfo(), blurStageInfo(),        fogStageInfo(),
                                             rainStageInfo()};
  return stages;
}

const StageInfo* findStage(const std::string& name) {
  for (const auto& s : allStages())
    if (s.spec.name == name) return &s;
  return nullptr;
}

SectionSpec cameraSection() {
  SectionSpec s;
  s.name = "camera";
  s.help = "The virtual camera that films the rain; match it to the plate's camera.";
  s.params = {
      {"fov_deg", ParamType::Number, 36.0, 1.0, 170.0, {}, "deg", "horizontal field of view"},
      {"exposure_s", ParamType::Number, 0.02, 1.0 / 8000.0, 1.0, {}, "s", "shutter time; sets the streak length"},
      {"fps", ParamType::Number, 0.0, 0.0, 240.0, {}, "1/s", "frame rate; 0 takes the clip's (24 for sequences)"},
      {"tilt_deg", ParamType::Number, 0.0, -89.0, 89.0, {}, "deg", "pitch of the camera, positive looking down"},
      {"height_m", ParamType::Number, 1.6, 0.0, 1000.0, {}, "m", "camera height above the ground plane"},
  };
  return s;
}

SectionSpec colorSection() {
  SectionSpec s;
  s.name = "color";
  s.help = "OpenColorIO colour spaces at the two ends; everything between is scene-linear float.";
  s.params = {
      {"input", ParamType::String, "auto", {}, {}, {}, "", "input colour space; auto: linear-rec709 for EXR/HDR, sRGB otherwise"},
      {"working", ParamType::String, "linear-rec709", {}, {}, {}, "", "scene-linear working space"},
      {"output", ParamType::String, "auto", {}, {}, {}, "", "output colour space; auto: linear-rec709 for EXR, sRGB otherwise"},
      {"config", ParamType::String, "", {}, {}, {}, "", "path of an .ocio config; empty uses pluvia's built-in one"},
  };
  return s;
}

Schema presetSchema() {
  Schema schema{cameraSection(), colorSection()};
  for (const auto& s : allStages()) schema.push_back(s.spec);
  return schema;
}

}  // namespace pluvia
