#include "stages/lights_at_frame.h"

#include <cmath>

namespace pluvia {

std::vector<optics::LocalLight> lightsAtFrame(const LightsSettings& settings, const Camera& camera,
                                              double frame) {
  std::vector<optics::LocalLight> out;
  const Eigen::Matrix3d cameraFromWorld = camera.worldFromCamera.transpose();
  for (size_t i = 0; i < settings.lights.size(); ++i) {
    const LightSpec& spec = settings.lights[i];
    optics::LocalLight light;
    Eigen::Vector3d position(spec.xMeters.valueAt(frame), spec.yMeters.valueAt(frame),
                             spec.zMeters.valueAt(frame));
    Eigen::Vector3d axis(spec.direction[0], spec.direction[1], spec.direction[2]);
    if (spec.worldFrame) {
      position = cameraFromWorld * (position - camera.positionMeters);
      axis = cameraFromWorld * axis;
    }
    const double intensity = spec.intensity.valueAt(frame);
    for (int c = 0; c < 3; ++c) light.rgbIntensity[size_t(c)] = intensity * spec.rgb[size_t(c)];
    light.positionMeters = {position.x(), position.y(), position.z()};
    light.radiusMeters = spec.radiusMeters;
    light.photographed = spec.photographed;
    if (spec.spot) {
      axis.normalize();  // of some length: lightsSettings refuses a spot without one
      light.spot = true;
      light.axis = {axis.x(), axis.y(), axis.z()};
      light.cosHalfAngle = std::cos(spec.halfAngleDeg.valueAt(frame) * M_PI / 180.0);
      light.falloffQ = spec.falloffQ;
    }
    out.push_back(light);
  }
  return out;
}

}  // namespace pluvia
