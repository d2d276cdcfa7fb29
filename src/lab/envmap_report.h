#pragma once
// `pluvia report envmap`: how well an environment stitched from a panning shot (panorama.h)
// stands in for the full HDR it was cut from, against the number of frames and the run time.
//
//  (a) Per HDR: one exposure for the shot, by average metering as a camera's meter does: over
//      a full turn at the report's pitch, the mean luminance of what the 8-bit camera records
//      (clipped) is put at mid-grey 0.18, so the sun, lamps and bright sky clip as they would.
//      Frames are recorded along a level-yawing pan (recordView: 8-bit sRGB with clipping),
//      yaw step min(hfov / 2, 360 / N) (about 50 % overlap, a full turn from 12 frames of 60°),
//      placed by placeFrames (true field of view given) and rendered by renderEquirect. The
//      stitcher places frame 0 level; the placement is turned onto frame 0's true orientation
//      (the camera's tilt is known on set) before rendering. Then, in the HDR's units (the
//      stitched map divided by the exposure):
//        SH error: relative L2 of the order-3 SH coefficients (16 per channel, R G B together);
//        drop colour error: buildDropRadianceMap (pluvia's default shading, eta 1.333, 20 terms)
//          of the stitched map against that of the HDR, looked up along view directions the pan
//          covered (a Fibonacci set inside the coverage); per direction the mean over R, G, B
//          of |stitched - full| / full, then mean and worst over the directions;
//        pose error: worst rotation angle between a placed and the true camera; focal error:
//          mean |f - f_true| / f_true.
//      The "+ lights" row re-renders the most frames with the paper's light-source replacement,
//      the radiances "measured when we captured the video" taken from the HDR: every connected
//      region of clipped pixels of every frame becomes a frame-region LightSource with the HDR's
//      mean radiance over those pixels; and where the pan did not see the sun, the sun becomes a
//      direction LightSource (direction of the HDR's brightest texel, disc of the solid angle
//      of the connected texels around it above max(clip level, 25 % of the peak), radiance
//      their mean: power kept).
//      The "sky model" rows re-render the most frames, as recorded and with those lights, with
//      the unseen sphere filled by UnseenFill::SkyModel (panorama.h) instead of the paper's
//      nearest seen colour (the rows above ask for Nearest); a table compares the four per
//      environment and names the sky each fit kept.
//  (b) Real photos (stitching/weir): placed with an unknown field of view (the focal is
//      estimated), the estimated yaws, pitches and field of view and the covered fraction.
#include <array>
#include <string>
#include <vector>

namespace pluvia::lab {

struct EnvmapReportSettings {
  std::string environment;  // one HDR; empty: every .exr/.hdr in sharedData/hdr, else built-in
  std::string sharedData;   // ../shared/data; empty or missing: the built-in environment only
  std::string imagesDir;    // when set: panoramas written here (PNG, EXR)
  bool quick = false;       // built-in environment, 640x360 frames, N = 3 and 12, no photos
  int frameWidth = 1280;
  int frameHeight = 720;
  double horizontalFovDeg = 60.0;
  double pitchDeg = 10.0;
  std::vector<int> frameCounts = {1, 3, 6, 12, 24};
  int panoramaWidth = 1024;  // of the stitched equirect map
  int directions = 200;      // view directions sampled inside the coverage
  double midGrey = 0.18;     // the recorded mean luminance over a full turn
};

struct EnvmapReportRow {
  std::string environment;  // file stem, or "builtin"
  int frames = 0;
  bool lightsRestored = false;  // the "+ lights" row
  bool skyModelFill = false;    // the unseen sphere filled by the sky model (else the nearest)
  std::string fillModel;        // what filled it ("nearest", "preetham T 3.1, sun at ...")
  int lights = 0;               // light sources given in that row
  double yawStepDeg = 0.0;
  bool fromFeatures = false;  // placement from matched features (false: the fallback)
  double poseErrorDeg = 0.0;
  double focalError = 0.0;  // fraction
  double coveredFraction = 0.0;
  double shError = 0.0;  // fraction
  double dropMeanError = 0.0;
  double dropMaxError = 0.0;
  int directions = 0;  // sampled in the covered band
  double placementSeconds = 0.0;
  double renderSeconds = 0.0;
};

struct EnvmapEnvironment {
  std::string name, path;
  int width = 0, height = 0;
  double exposure = 0.0;         // radiance x exposure = 1 is the camera's white
  double peak = 0.0;             // brightest texel's luminance, HDR units
  double clippedFraction = 0.0;  // of the sphere (solid angle) above the clip level
  bool sun = false;              // something clipped: a light source to restore
  double sunElevationDeg = 0.0, sunAzimuthDeg = 0.0, sunRadiusDeg = 0.0;
  std::array<float, 3> sunRadiance{0, 0, 0};  // HDR units
  bool sunSeen = false;                       // inside the widest pan's coverage
};

struct EnvmapRealPhotos {
  bool present = false;
  std::string folder;
  int frames = 0;
  int width = 0, height = 0;
  bool fromFeatures = false;
  std::string note;
  std::vector<double> yawDeg, pitchDeg, focalPx, hfovDeg;
  double coveredFraction = 0.0;
  double placementSeconds = 0.0, renderSeconds = 0.0;
  double saturatedFraction = 0.0;  // of the photos' pixels
};

struct EnvmapReport {
  int frameWidth = 0, frameHeight = 0;
  double horizontalFovDeg = 0.0, pitchDeg = 0.0;
  int panoramaWidth = 0;
  std::vector<EnvmapEnvironment> environments;
  std::vector<EnvmapReportRow> rows;
  EnvmapRealPhotos real;
  std::vector<std::string> notes;  // missing data, images written
};

// Throws pluvia::Error naming the file when an HDR cannot be read or an image cannot be
// written. Missing shared data is not an error: a note says what was left out.
EnvmapReport runEnvmapReport(const EnvmapReportSettings& settings);

// The report's targets: drop colour error in covered directions, and seconds to stitch 24
// frames of 720p.
inline constexpr double kEnvmapDropColourTarget = 0.10;
inline constexpr double kEnvmapStitchSecondsTarget = 30.0;

// A row's label in the table and the plot: its frame count and what was added ("24+lights").
std::string envmapRowLabel(const EnvmapReportRow& row);

// The report as text (envmap_report_text.cpp, with the CSV; the plot in envmap_report_plot.cpp).
std::string formatEnvmapReport(const EnvmapReport& report);
// One line per row.
void writeEnvmapReportCsv(const EnvmapReport& report, const std::string& path);
// Mean drop colour error (log) against stitching time (placement + rendering, log), one line
// per environment through its frame counts, the "+ sun" rows as markers.
void writeEnvmapReportPlot(const EnvmapReport& report, const std::string& path);

}  // namespace pluvia::lab
