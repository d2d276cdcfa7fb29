#include "stages/registry.h"

#include <limits>

namespace pluvia {

const std::vector<StageInfo>& allStages() {
  static const std::vector<StageInfo> stages{
      derainStageInfo(), environmentStageInfo(), depthStageInfo(), darkenStageInfo(),
      blurStageInfo(),   fogStageInfo(),         rainStageInfo()};
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
  constexpr double kInf = std::numeric_limits<double>::infinity();
  auto number = [](const char* key, nlohmann::json value, double min, double max, const char* units,
                   const char* help) {
    return ParamSpec{key, ParamType::Number, std::move(value), min, max, {}, units, help};
  };
  // camera.path: poses over clip frames (geometry/camera_path.h has the angle conventions).
  ParamSpec path = number("path", nlohmann::json::array(), 0, 0, "",
                          "poses over clip frames, interpolated between keys, held outside them; "
                          "empty: a static camera from tilt_deg and height_m");
  path.type = ParamType::List;
  path.orderedBy = "frame";
  ParamSpec frame = number("frame", nullptr, -kInf, kInf, "", "clip frame number of this key");
  frame.required = true;
  ParamSpec position = number("position_m", nullptr, -kInf, kInf, "m", "camera position, +Y up");
  position.type = ParamType::Vector3;
  position.required = true;
  path.itemTypes = {
      {"",
       {frame, position,
        number("yaw_deg", 0.0, -kInf, kInf, "deg", "positive turns right, from -Z toward +X"),
        number("pitch_deg", 0.0, -90.0, 90.0, "deg", "positive looks up (= -tilt_deg)"),
        number("roll_deg", 0.0, -180.0, 180.0, "deg",
               "positive: the view's right side goes down")}}};
  s.params = {
      number("fov_deg", 36.0, 1.0, 170.0, "deg", "horizontal field of view"),
      number("exposure_s", 0.02, 1.0 / 8000.0, 1.0, "s", "shutter time; sets the streak length"),
      number("shutter_angle_deg", 0.0, 0.0, 360.0, "deg",
             "when > 0: exposure = shutter_angle / 360 / fps, overriding exposure_s; 0: unused"),
      number("fps", 0.0, 0.0, 240.0, "1/s", "frame rate; 0 takes the clip's (24 for sequences)"),
      number("tilt_deg", 0.0, -89.0, 89.0, "deg", "pitch of the camera, positive looking down"),
      number("height_m", 1.6, 0.0, 1000.0, "m", "camera height above the ground plane"),
      number("focus_m", 20.0, 0.0, 1e6, "m",
             "focus distance (the default depth's backdrop); 0: no defocus"),
      number("f_number", 11.0, 0.0, 128.0, "", "aperture f-number; 0: pinhole, no defocus"),
      number("sensor_width_mm", 36.0, 1.0, 100.0, "mm",
             "sensor width; with fov_deg gives the focal length (defocus)"),
      path,
  };
  // The exposure may ramp (the rain stage reads it per frame); the rest is fixed for the shot.
  allowKeyframes(s.params, {"exposure_s"});
  return s;
}

SectionSpec colorSection() {
  SectionSpec s;
  s.name = "color";
  s.help = "OpenColorIO colour spaces at the two ends; everything between is scene-linear float.";
  s.params = {
      {"input",
       ParamType::String,
       "auto",
       {},
       {},
       {},
       "",
       "input colour space (name, alias or role); auto: scene_linear for EXR/HDR, the config's "
       "sRGB space otherwise (--in-colorspace)"},
      {"working",
       ParamType::String,
       "scene_linear",
       {},
       {},
       {},
       "",
       "scene-linear working space (the config's scene_linear role by default)"},
      {"output",
       ParamType::String,
       "auto",
       {},
       {},
       {},
       "",
       "output colour space; auto: the working space for EXR/HDR, the config's sRGB space "
       "otherwise (--out-colorspace)"},
      {"config",
       ParamType::String,
       "",
       {},
       {},
       {},
       "",
       "path of an .ocio config; empty: $OCIO, else pluvia's built-in one"},
  };
  return s;
}

Schema presetSchema() {
  Schema schema{cameraSection(), colorSection()};
  for (const auto& s : allStages()) schema.push_back(s.spec);
  return schema;
}

}  // namespace pluvia
