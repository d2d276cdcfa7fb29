#pragma once
// `pluvia match`: what a preset needs to reproduce the rain of a reference clip of real rain.
// The reference's clean plates are made once (lab/real_rain_clip.h); candidates are rendered on
// them, and their streaks measured as the reference's are: frames minus clean plates estimated
// from those frames, then the statistics of `pluvia report realism`. Four numbers set the
// streaks' statistics, and each statistic answers more than one of them:
//  - the shutter (camera.exposure_s) sets the streaks' length (about exposure^0.4 at video
//    scales), and a longer one also dims them (exposure^-0.39: a drop's light spread along a
//    longer streak) and thins them out (fewer pass the threshold);
//  - the rate (rain.rate_mm_h) their number per megapixel and the share of pixels they cover;
//  - the farthest drops drawn (rain.far_m) how deep the rain is seen: real footage often shows
//    only its near drops (NTURain's streaks are twice as long as pluvia's drawn to 8 m, and its
//    frames carry no pepper of faint far specks; matched at 1.7 m), so a nearer far_m thins out
//    the short faint streaks of far drops, which brightens the streaks left and lets a longer
//    shutter lengthen them without losing them under the threshold;
//  - the wind across the view (rain.wind, toward the camera's right or left) their angle, by the
//    secant through the steps with the most different winds (at first about 13 degrees of streak
//    per m/s, a 4.5 m/s fall).
// The opacity stays the base preset's (the physical streak's 1 for the shipped ones): it moves
// the count as a rate does and hardly the brightness, so it cannot be told from the rate.
// Each step moves from the best step so far: the rate and exposure by the step that fixed response
// predicts lowers the typical factor most (its mean |log ratio|, which a least-squares step would
// not: it traded the three brightness ratios for the length's one), the wind on the angle; a step
// that does worse halves the next. Steps are scored by the typical factor
// (derain::typicalFactor, which leaves the angle out) times exp(|angle error| / 10 deg); the best
// is the match. A reference whose streaks do not agree on a direction (their angles spread more
// than kMaxMatchedAngleSpreadDeg: a fast camera's misregistration or moving things outweigh the
// rain's own lean) has no angle to match: the wind stays the base preset's, untouched.
#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "derain/streak_stats.h"

namespace pluvia::lab {

struct RainLook {
  double rateMmPerHour = 8.0;
  double exposureSeconds = 1.0 / 250.0;
  double opacity = 1.0;
  double farMeters = 8.0;                 // rain.far_m
  double windRightMetersPerSecond = 0.0;  // toward the camera's right; negative: its left
  bool baseWind = false;  // true: the base preset's wind, left as it is (no overrides)
};

// Above this spread of its streaks' angles (derain::StreakStats::angleSpreadDeg) a reference's
// angle is not matched. NTURain ra1 spreads 11 deg, pluvia's gusty `moderate` on its plates 25;
// NTURain's vehicle clip rb2, whose layer holds the fast camera's misregistration, 40 (its
// measured angle, -59 deg, is not the rain's, about -30 by eye).
inline constexpr double kMaxMatchedAngleSpreadDeg = 30.0;

// The preset overrides ("rain.rate_mm_h=...") that render `look`.
std::vector<std::string> lookOverrides(const RainLook& look);

struct RainMatchSettings {
  std::string clip;  // real rain footage
  int frames = 24;   // its first frames measured
  int widthPx = 640;
  int steps = 6;  // renders
  RainLook start;
  // rain.far_m stays above this (the drops must lie beyond near_m: at least 1 m, twice a base's
  // own near_m).
  double minFarMeters = 1.0;
};

// Renders the reference's clean plates (RGB codes) at `fps`, filmed `filmedWidthPx` wide, with
// the base preset and these overrides; returns the rained frames in the same encoding.
using RenderLook = std::function<std::vector<cv::Mat3f>(const std::vector<cv::Mat3f>& plates,
                                                        double fps, int filmedWidthPx,
                                                        const std::vector<std::string>& overrides)>;

struct RainMatchStep {
  RainLook look;
  derain::StreakStats stats;
  std::vector<std::pair<std::string, double>> ratios;  // to the reference
  double typical = 0.0;
  double seconds = 0.0;
};

struct RainMatch {
  std::string clip;  // its name
  derain::StreakStats reference;
  bool angleMatched = true;  // false: its streaks spread too widely (kMaxMatchedAngleSpreadDeg)
  std::vector<RainMatchStep> steps;
  size_t best = 0;  // index into steps
};

// Throws pluvia::Error naming the clip when it cannot be read or shows no rain streaks.
RainMatch matchRain(const RainMatchSettings& settings, const RenderLook& render);

std::string formatRainMatch(const RainMatch& match);

}  // namespace pluvia::lab
