#pragma once
// A local light of one frame (a lamp, a spotlight) in camera space: what the lights stage
// places, the halo renderer (optics/light_halos.h) and the lit drops (optics/drop_local_light.h)
// shine, and the glare stage spreads.
#include <array>

namespace pluvia::optics {

using Vec3 = std::array<double, 3>;

struct LocalLight {
  Vec3 positionMeters{0, 0, 0};  // camera frame
  // Radiant intensity per channel: a surface facing the light at d metres receives the
  // irradiance rgbIntensity / d^2, in the working space's linear units.
  std::array<double, 3> rgbIntensity{0, 0, 0};
  double radiusMeters = 0.05;  // the bulb: rays closer than this to the centre see it
  // Spotlight cone (spot): axis (unit, from the light), cos A and Huang et al.'s fall-off q of
  // I(theta) (spotFactor).
  bool spot = false;
  Vec3 axis{0, 0, -1};
  double cosHalfAngle = 0.0;
  double falloffQ = 0.0;
  // A lamp found in the plate: its image and its bloom are already photographed (no glare).
  bool photographed = false;
};

// The spot's I(theta) / I0 at cos(theta) (1 for a point light): Huang et al.'s
// (1 - q)(cos theta - cos A) / (1 - cos A) + q inside the cone, 0 outside.
double spotFactor(const LocalLight& light, double cosTheta);

}  // namespace pluvia::optics
