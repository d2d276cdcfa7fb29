#pragma once
// The principal rain direction D0 (Wang et al. section 2): streaks along a direction put their
// spectral energy on the line through the origin perpendicular to it, so the most salient line
// through the origin of the mattes' 2-D power spectrum gives the rain angle. The spectrum is
// taken over 96 px tiles, each voting for its own most salient line, and the line most tiles
// agree on wins: rain covers the frame, the other structure left in real mattes is local.
#include <vector>

#include <opencv2/core.hpp>

namespace pluvia::derain {

struct RainAngleEstimate {
  double angleDeg = 0.0;  // frame_stack.h convention
  // Over the tiles, the geometric mean of the energy on the found line over the mean energy
  // over all lines: 1 when the line is no stronger than any other.
  double salience = 1.0;
  // The share of the tiles' votes (each tile's best line, weighted by how much it stands out)
  // within 2.5 degrees of the found line: 1 when every tile sees it, small when they disagree.
  double agreement = 0.0;
};

// `mattes`: CV_32FC1, all the same size. Each is windowed (Hann) and mean-subtracted before
// its spectrum is taken, so the frame border puts no false vertical or horizontal line in it.
// Only streak angles within `maxAngleDeg` of the vertical are searched: on real footage the
// scene's horizontal lines (rails, roofs, kerbs, compression blocks) leave more energy in the
// mattes than short rain streaks, and rain is not seen falling near-horizontal (that takes a
// wind several times the terminal velocity). 90 searches every direction.
// With no structure (all zero) returns angle 0, salience 1 and agreement 0.
RainAngleEstimate estimateRainAngle(const std::vector<cv::Mat>& mattes, double maxAngleDeg = 60.0);

}  // namespace pluvia::derain
