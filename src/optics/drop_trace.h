#pragma once
// The reference for every drop-shading approximation: a Monte-Carlo ray tracer of one water
// sphere lit by an equirect environment. Independent of the closed form in drop_transfer.h: it
// intersects rays with the sphere in 3-D and applies Snell's law and unpolarised Fresnel
// reflectance at every interface, splitting each path into its reflected and refracted parts
// until the power left inside the drop is negligible.
//
// What it computes: the radiance a camera sees from a drop, averaged over the drop's disc, along
// the unit view direction (camera -> drop). By reciprocity this is the integral of D(theta) L(w)
// over directions w, theta the angle between the view direction and w.
#include <array>
#include <cstdint>

#include "image/equirect.h"

namespace pluvia::optics {

struct TraceSettings {
  // Rays through the disc, stratified on a k x k grid in (b^2, phi), k = round(sqrt(samples)).
  // The default keeps the noise near 0.5 % even with a sun in view (see the optics report).
  int samples = 262144;
  double minPower = 1e-7;      // a path ends when the power left inside falls below this
  int maxInteractions = 2000;  // and at most this many interfaces (the entry counts as one)
  uint64_t seed = 1;           // jitter of the stratified samples
};

// Linear RGB radiance of the drop; eta: refractive index of water relative to air per channel.
// Throws std::invalid_argument for an empty map, a zero or non-finite view direction (any other
// length is normalised), eta outside (1, 3], samples < 1.
std::array<double, 3> traceDropRadiance(const EquirectMap& environment,
                                        const std::array<double, 3>& viewDirection,
                                        const std::array<double, 3>& eta,
                                        const TraceSettings& settings);

}  // namespace pluvia::optics
