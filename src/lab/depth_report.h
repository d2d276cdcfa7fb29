#pragma once
// `pluvia report depth`: camera tracking and depth from structure from motion (COLMAP through
// sfm/clip_tracking.h) against ground truth, and against run time.
//
//  (a) Synthetic: the street of lab/synthetic_scene.h rendered through the project's own EGL
//      code along defaultSyntheticPath(48) (a 2.35 m walk at 1.6 m, 4 degrees of yaw), frames
//      sRGB-encoded (8-bit PNG, as a camera's file), at 1280x720, 640x360 and 320x180, with every
//      frame or every 2nd or 4th handed to COLMAP (the poses of the others interpolated). Per row:
//      frames with a pose, pose error after aligning the SfM world to the truth (lab/pose_error.h:
//      chordal-mean rotation, translation, no scale re-fit; the scale ratio on its own), and the
//      densified depth of every 8th frame against the exact z-depth: median relative error
//      (pooled over those frames; also split by ground, walls and boxes), how much true sky comes
//      out +inf and how much of the rest does. Time: COLMAP, densification per frame, and the
//      total for the clip (tracking without rendering + densifying all its frames, estimated
//      from the evaluated ones).
//  (b) Real photos (sfm/opensfm_lund, 29 street photos downscaled to 800 px, hfov guessed 75
//      degrees): the fraction registered, the mean reprojection error, the time.
#include <string>
#include <vector>

namespace pluvia::lab {

struct DepthReportSettings {
  std::string sharedData;    // ../shared/data; empty or missing: no real photos
  std::string imagesDir;     // when set: depth vs truth previews (PNG) of each synthetic row
  std::string colmapBinary;  // empty: $PLUVIA_COLMAP, else "colmap"
  std::string workspace;     // COLMAP's folders, kept; empty: a temporary folder, removed
  bool quick = false;        // one row, every 4th frame (13) at 1280x720, no photos
};

struct DepthReportRow {
  int clipFrames = 0;  // frames of the synthetic clip
  int frameStep = 0;   // every Nth frame tracked; 0: chosen by parallax (the default)
  int framesUsed = 0;  // handed to COLMAP
  int width = 0, height = 0;
  std::string status;  // "ok", an SfM status ("no_ground_plane"...), or "failed"
  std::string message;
  int registeredUsed = 0;  // of framesUsed, registered by COLMAP
  int framesWithPose = 0;  // of clipFrames, between the first and last registered frame
  double rotationMeanDeg = 0.0, rotationMaxDeg = 0.0;
  double positionMeanMeters = 0.0, positionMaxMeters = 0.0;
  double scaleRatio = 0.0;  // estimate / truth
  double levelErrorDeg = 0.0;
  double heightOffsetMeters = 0.0;
  double focalError = 0.0;  // |f - f_true| / f_true
  double reprojectionPx = 0.0;
  int depthFrames = 0;  // evaluated
  double depthMedian = 0.0, depthP90 = 0.0;
  double depthMedianGround = 0.0, depthMedianWalls = 0.0, depthMedianBoxes = 0.0;
  double skyAsInfinity = 0.0, nonSkyAsInfinity = 0.0;
  double renderSeconds = 0.0;    // rendering the frames COLMAP got (not counted in the total)
  double colmapSeconds = 0.0;    // the four COLMAP steps
  double trackingSeconds = 0.0;  // frame export + COLMAP + model import (rendering excluded)
  double densifySecondsPerFrame = 0.0;
  double totalSeconds = 0.0;  // tracking + densifying every clip frame (estimated)
};

struct DepthReportReal {
  bool present = false;
  std::string folder;
  std::string note;  // why it is absent, or the SfM message
  std::string status;
  int photos = 0, registered = 0;
  int width = 0, height = 0;  // as handed to COLMAP
  double registeredFraction = 0.0;
  double reprojectionPx = 0.0;
  double baselineOverDepth = 0.0;
  double seconds = 0.0;
};

struct DepthReport {
  std::string device;  // the GL renderer
  std::vector<DepthReportRow> rows;
  DepthReportReal real;
  std::vector<std::string> notes;
};

// Throws pluvia::Error when COLMAP is not installed, no GL context can be made, or an image
// cannot be written. A COLMAP failure on one row is that row's status, not an error.
DepthReport runDepthReport(const DepthReportSettings& settings);

// The report's targets and its fixed choices.
inline constexpr double kDepthReportRotationTargetDeg = 0.5;
inline constexpr double kDepthReportDepthTarget = 0.10;
inline constexpr double kDepthReportSecondsTarget = 300.0;  // 48 frames of 720p
inline constexpr int kDepthReportEvaluationFrames = 6;  // depth compared on every clipFrames/6-th
inline constexpr double kLundHfovDeg = 75.0;  // the Lund photos' phone (focal ~0.65 of the width)
inline constexpr const char* kLundFolder = "sfm/opensfm_lund";

// A row's label: frames used of the clip's, size, and how frames were chosen.
std::string depthRowLabel(const DepthReportRow& row);

// The report as text (depth_report_text.cpp, with the CSV; the plot in depth_report_plot.cpp).
std::string formatDepthReport(const DepthReport& report);
// One line per synthetic row, then the real photos' line (scene "opensfm_lund").
void writeDepthReportCsv(const DepthReport& report, const std::string& path);
// Two panels against the total time (log): the worst rotation error and the median depth error.
void writeDepthReportPlot(const DepthReport& report, const std::string& path);

}  // namespace pluvia::lab
