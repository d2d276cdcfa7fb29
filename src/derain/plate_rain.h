#pragma once
// Whether a plate was shot in rain: its own streaks, found the way `pluvia report realism` finds
// real rain (clean_plate.h, streak_stats.h). A plate already holds the veil of the rain it was
// shot in, so the grading stages (darken, blur, fog) leave it out there unless asked.
//
// The frames are consecutive, BGR display codes (0..255) at about 640 px wide; the middle
// `measuredFrames` of them get a clean plate each (from up to 3 neighbours either side) and the
// layer frame - plate is searched for streaks, false alarms (the negated layer) subtracted.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "derain/streak_stats.h"

namespace pluvia::derain {

struct PlateRainSettings {
  int measuredFrames = 3;
  // Rained when both hold. Real rain at 640 px: NTURain's light shower covers 1.1 % with 990
  // streaks per Mpx; a dry street with walkers measures 0 and under 40.
  double minCoverage = 0.002;
  double minStreaksPerMpx = 200.0;
};

struct PlateRain {
  bool rained = false;
  StreakStats stats;
  int frames = 0;  // measured
  // Why nothing was measured (frames too small to follow), "" when the frames were.
  std::string unmeasured;
  // "streaks over 1.1 % of the frame, 990 per Mpx, falling at 0.2 deg (3 frames measured)"
  std::string summary() const;
};

// Throws pluvia::Error when there are fewer than 3 frames or they differ in size. Frames too
// small to follow their motion (derain/dense_flow.h) are not rained, and `unmeasured` says why.
PlateRain measurePlateRain(const std::vector<cv::Mat3f>& bgrFrames,
                           const PlateRainSettings& settings = {});

}  // namespace pluvia::derain
