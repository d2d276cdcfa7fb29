#include "preset/camera_path_preset.h"

namespace pluvia {

CameraPath cameraPathFromPreset(const Preset& preset, const Camera& base) {
  if (!preset.has("camera.path")) return CameraPath::fixed(base);
  const nlohmann::json& items = preset.at("camera.path");
  if (!items.is_array() || items.empty()) return CameraPath::fixed(base);
  std::vector<std::pair<double, CameraPose>> keys;
  for (const auto& item : items) {
    CameraPose pose;
    const nlohmann::json& p = item.at("position_m");
    pose.positionMeters = {p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>()};
    pose.yawDeg = item.value("yaw_deg", 0.0);
    pose.pitchDeg = item.value("pitch_deg", 0.0);
    pose.rollDeg = item.value("roll_deg", 0.0);
    keys.emplace_back(item.at("frame").get<double>(), pose);
  }
  return CameraPath::fromKeys(base, std::move(keys));
}

}  // namespace pluvia
