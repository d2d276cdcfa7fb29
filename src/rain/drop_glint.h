#pragma once
// The glint of a local light in an oscillating drop (Garg and Nayar 2006, Sec. 2-3): the drop's
// shape r = r0 (1 + A(2,0) sin(w2 t) P(2,0)(cos theta) + A(3,1) sin(w3 t) cos(phi) P(3,1)(cos
// theta)), theta from the vertical (the drop falls through still air in its own frame). A
// point light's glint is as bright as 1 / K, K the Gaussian curvature of the surface where its
// normal is the half vector h between the directions to the light and to the camera; to first
// order in the amplitudes a mode (n, m) multiplies K by 1 + (n - 1)(n + 2) A Y(h) (the
// curvature of a perturbed sphere, the same factor as Rayleigh's restoring pressure). So the
// glint beads along the streak with both modes' frequencies, and how deeply depends on where h
// points: mode (2, 0) vanishes at 54.7 deg from the vertical, mode (3, 1) at the poles and at
// 63.4 deg. The refracted glints are taken to bead like the reflected one.
#include <array>

#include "rain/streak_types.h"

namespace pluvia::rain {

// The two shape sets Garg and Nayar found to match real streaks: (A(2,0), A(3,1)) = (0.2, 0.1)
// and (0.1, 0.1).
inline constexpr float kOscillationAmplitude20[2] = {0.2f, 0.1f};
inline constexpr float kOscillationAmplitude31 = 0.1f;

// The glint's log-curvature amplitudes for a drop of shape amplitudes A(2,0) and A(3,1)
// cos(phi_rot), h at cos(theta) = cosHalfFromUp from the vertical: 4 A(2,0) P(2,0) and
// 10 A(3,1) cos(phi_rot) P(3,1), with P(2,0)(x) = (3 x^2 - 1) / 2 and P(3,1)(x) = 3/2 (5 x^2 -
// 1) sqrt(1 - x^2) (the associated Legendre functions, unnormalised as in Garg and Nayar).
std::array<float, 2> glintModes(float amplitude20, float amplitude31CosPhi, double cosHalfFromUp);

// The mean of localLightBead() over the streak (v from 0 to 1), by the midpoint rule with at
// least 16 samples per period of mode (3, 1) (at most 512).
float streakMeanBead(float cycles, float phase, float mode20, float mode31);

// The mean of localLightBead() over every phase of the drop's oscillation (what a sphere's glint
// averages to across many drops): the bead is normalised by it so that the oscillation moves the
// glint's light between drops and along streaks, not adds to it.
float oscillationMeanBead(float mode20, float mode31);

// Turns the streak's shape amplitudes into the glint's for the light at unit direction
// `towardsLight` from the drop, seen from unit `towardsCamera`, `up` the vertical (all in one
// space), and divides its local radiance by oscillationMeanBead(). A light straight behind the
// drop (h undefined) takes h = towardsCamera.
void shapeGlint(StreakInstance& streak, const std::array<double, 3>& towardsLight,
                const std::array<double, 3>& towardsCamera, const std::array<double, 3>& up);

}  // namespace pluvia::rain
