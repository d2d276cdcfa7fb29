#pragma once
// `pluvia report realism`: the look's own error report. Rain rendered by pluvia against real rain
// footage, on the same clean plates, by the statistics of the visible streaks.
//
// For each real rain clip: the frames scaled to kReportWidthPx wide; a clean plate per frame
// (clean_plate.h: a registered temporal median of +-3 frames, the flow taken only where it
// explains the neighbours better than identity, moving things masked); the real rain layer
// dI = luma(frame) - luma(plate) in 8-bit display codes, with its validity mask. Each preset is
// rendered on those plates (by the caller: RenderOnPlates) with darken, blur and fog off, so the
// streaks alone are compared, and its layer is measured the same way: against clean plates
// estimated from the rendered frames by the same estimator (streak_stats.h: visible streaks,
// dI > 10 codes and a ridge, false alarms from the negated layer subtracted). The estimator keeps
// part of any rain in its plates and masks what it cannot register, so the real layer is the real
// rain as the estimator sees it; measured against the plates it was rendered on, pluvia's rain
// would skip that loss: pluvia's own rain, rendered again with its own preset on its own
// estimated plates, then scored x1.28 (coverage x2.06, count x1.59), against x1.05 measured this
// way.
// Each preset's statistics are given as ratios to the real ones, each judged against the bound
// kRealismBound (marked when outside it), with the worst of them and the typical factor,
// exp(mean |ln ratio|) over coverage, dI p90, dI p99, streaks per Mpx, length p50, width p50,
// peak p90 and the elongation by light (the shape of the streaks the light is in: dashes or
// flecks). The nearest preset is the one whose worst statistic is nearest to real: a look is
// met when every statistic is, not on average. Each clip's own shutter, as a render of the clip
// finds it (derain/motion_blur.h: its motion blur, or under that the streaks of its rain, or the
// 180-degree shutter), is in the notes: the presets film the rain with it (camera.exposure_s 0;
// the clean plates hold no rain to time it by). With it each row's streaks are inverted into
// their drops' contrast (derain::impliedDropContrastCodes): the light a drop brings, apart from
// how the shutter and the blur spread it.
//
// The ground row (lab/ground_layer.h): what lands, the layer's roundish blobs over the frame's
// bottom third, each preset's against real by the same ratios, judged against kGroundBound.
#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "derain/streak_stats.h"
#include "lab/ground_layer.h"

namespace pluvia::lab {

using derain::StreakStats;

// The statistics are taken at this width (the frames are scaled to it, keeping their aspect).
inline constexpr int kReportWidthPx = 640;
// A statistic is met within this factor of real, either way.
inline constexpr double kRealismBound = 1.25;
// The ground's statistics are met within this factor (issue 58).
inline constexpr double kGroundBound = 1.5;

struct RealismReportSettings {
  std::vector<std::string> clips;    // real rain clips; empty: NTURain ra1 from sharedData
  std::vector<std::string> presets;  // rendered and measured, by name or path
  std::string sharedData;            // ../shared/data; empty: only the clips given
  std::string imagesDir;             // when set: the contact sheets, PNG
  int frames = 24;                   // measured per clip (its first ones)
  bool quick = false;                // 8 frames at 320 px wide (for tests)
};

// Renders `preset` over the clean plates (RGB, 8-bit display codes as float 0-255, one per
// frame, a clip at `fps`, filmed `filmedWidthPx` wide: the camera whose rain the preset draws,
// with the clip's own shutter, `shutterSeconds`, where the preset leaves it to the plate) and
// returns the rendered frames in the same encoding, rounded to 8-bit codes as a video frame is.
using RenderOnPlates = std::function<std::vector<cv::Mat3f>(
    const std::vector<cv::Mat3f>& plates, double fps, int filmedWidthPx, double shutterSeconds,
    const std::string& preset)>;

struct RealismRow {
  std::string clip;    // its file name
  std::string preset;  // "real" for the footage's own rain
  StreakStats stats;
  std::vector<std::pair<std::string, double>> ratios;  // to the real row (empty for it)
  double typical = 0.0;                                // typicalFactor(ratios); 1 for real
  double worst = 0.0;  // the largest max(r, 1/r) over the ratios; 1 for real
  std::string worstName;
  // The same layer taken against the exact plates it was rendered on (rendered - plate), not
  // re-estimated: the method that skips the estimator's loss (above); empty for the real row.
  StreakStats exactStats;
  std::vector<std::pair<std::string, double>> exactRatios;
  double exactTypical = 0.0, exactWorst = 0.0;
  GroundStats ground;  // its layers' ground (lab/ground_layer.h)
  std::vector<std::pair<std::string, double>> groundRatios;  // to the real row's
  double groundWorst = 0.0;
  GroundStats groundExact;      // of the layer against the exact plates (empty for the real row)
  double shutterSeconds = 0.0;  // the clip's own (its drops' implied contrast needs it)
  double seconds = 0.0;         // plates (real) or render + measure
};

struct RealismReport {
  int widthPx = 0;
  std::vector<RealismRow> rows;  // per clip: the real row, then each preset's
  // missing data, images written, each clip's shutter, the nearest preset per clip
  std::vector<std::string> notes;
};

// Throws pluvia::Error naming the clip when a clip given cannot be read; the default clip
// missing is a note, not an error.
RealismReport runRealismReport(const RealismReportSettings& settings, const RenderOnPlates& render);

std::string formatRealismReport(const RealismReport& report);
void writeRealismReportCsv(const RealismReport& report, const std::string& path);
// The ratios to real per statistic (log scale), one line per preset, one panel per clip.
void writeRealismReportPlot(const RealismReport& report, const std::string& path);

}  // namespace pluvia::lab
