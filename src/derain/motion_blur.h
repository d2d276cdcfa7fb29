#pragma once
// The plate camera's shutter, measured from the plate's own motion blur. An edge that moves v px
// a frame while the shutter is open for a fraction f of the frame time (the shutter angle over
// 360 deg) is smeared, across its normal n, into a ramp L = f |v . n| px long, on top of the
// blur every edge has (lens, sensor, demosaicing, codec: a Gaussian of sigma px). The profile's
// steepest slope is then its contrast over the width
//   w(L, sigma) = L / erf(L / (2 sqrt(2) sigma))     (sqrt(2 pi) sigma at L = 0),
// so the widths of many edges set against how fast each moves across itself give f and sigma
// together: edges moving along themselves (|v . n| near 0, every pan has them) fix sigma, the
// ones moving across themselves the shutter. Velocities are the dense flow to the frames either
// side (their half difference: the motion at the middle of the frame's exposure).
//
// The frames are greys in linear light (the blur adds light, so a ramp is straight there).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace pluvia::derain {

struct ShutterFromBlur {
  bool measured = false;
  double shutterFraction = 0.0;  // exposure over frame time; 0 when not measured
  // The blur was too short to see on the fastest edges: shutterFraction is the shortest shutter
  // those edges could show, an upper bound.
  bool upperBound = false;
  double sigmaPx = 0.0;  // the blur of a still edge, at the measured size
  // The blur of a still edge at the frames' own size: the edges that do not move across
  // themselves (their median width over sqrt(2 pi)), as every plate has them, static or panning;
  // with fewer than kMinStillEdges of them the fit's sigma where the shutter is measured, else 0.
  double stillBlurPx = 0.0;
  int edges = 0;        // edge profiles fitted
  int movingEdges = 0;  // of those, moving across themselves kMovingPx a frame or more
  // The middle half of the per-frame estimates, as fractions of the shutter (0 with one frame).
  double lowFraction = 0.0, highFraction = 0.0;
  std::string summary;  // what was measured, or why it could not be
};

// An edge counts as moving when it crosses kMovingPx or more of itself a frame; the fit needs
// kMinMovingEdges of them, spread over at least two speeds.
inline constexpr double kMovingPx = 2.0;
inline constexpr int kMinMovingEdges = 150;
inline constexpr int kMinStillEdges = 150;

// The width model above, in px.
double blurredEdgeWidthPx(double rampPx, double sigmaPx);

// The other clock a plate may hold: the streaks of rain already in it. A drop of diameter D
// falling at v(D) past the camera draws a streak v T f / z + D f / z long and D f / z wide
// (Garg and Nayar), so T = (L / W - 1) D / v, and D / v(D) hardly depends on D (Atlas's fall
// speeds: 0.25 ms at 0.5 and 1 mm, 0.31 ms at 2 mm, 0.37 ms at 3 mm; dropSecondsPerDiameter(), at
// 1.5 mm). That holds for a drop resolved wider than the lens and the pixels blur it. Most
// streaks are far drops' no wider than that blur, whose L / W reads the shutter short by their
// width over their drop's (NTURain at 640 px: median streak 6.0 x 1.16 px, L / W 5.2); the
// streaks the light is in are the near drops', resolved (there L / W 7.5). Seconds for streaks
// whose length over width, the median weighted by their light (StreakStats'
// elongationByLightP50), is `elongationByLight`; 0 when not over 1.
double shutterFromStreaksSeconds(double elongationByLight);
// D / v(D) at D = 1.5 mm, the seconds a drop takes to fall its own diameter.
double dropSecondsPerDiameter();

// `greys`: 3 or more consecutive frames (CV_32F, linear light, one size). Frames wider than
// 1024 px are measured at 1024 px (the shutter fraction does not depend on the scale). Throws
// pluvia::Error for fewer than 3 frames or frames of different sizes.
ShutterFromBlur measureShutterFromBlur(const std::vector<cv::Mat1f>& greys);

}  // namespace pluvia::derain
