#pragma once
// Runs COLMAP's sparse pipeline (feature_extractor, sequential_matcher, mapper, model_converter;
// bundle_adjuster to free the intrinsics after mapping with them held)
// on frames already written to disk, CPU only: COLMAP 3.8 here is built without CUDA and aborts
// headless unless SIFT runs on the CPU (see ../shared/PLATFORM.md).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pluvia::sfm {

struct ColmapRequest {
  // The frames, already written. File names (not folders) must be unique: COLMAP identifies
  // images by name, and sfm_poses.h maps names back to clip frames.
  std::vector<std::filesystem::path> images;
  // Holds images/ (links to the frames), database.db, sparse/<n>/, text/, model/ (the result)
  // and colmap.log.
  // A previous run's database and models there are removed first.
  std::filesystem::path workspace;
  // A starting focal length; without it COLMAP guesses 1.2 * max(width, height).
  std::optional<double> initialFocalPx;
  std::string cameraModel = "SIMPLE_RADIAL";  // or "PINHOLE", "SIMPLE_PINHOLE", "RADIAL"
  int maxImageSizePx = 1600;   // SIFT works on frames downscaled to this longest side
  int sequentialOverlap = 10;  // each frame is matched with this many following ones
  // The mapper's minimum triangulation angle for its first pair. COLMAP's 16 deg suits photo
  // collections; neighbouring video frames (and forward walks) see each other at a few degrees,
  // and with 16 the mapper picks distant, weakly matched pairs and fails (opensfm_lund).
  double initMinTriAngleDeg = 4.0;
  // Minimum inliers for the first pair (COLMAP's 100: fewer lets it start from a distant pair
  // whose few points the next frames cannot see) and to register each further frame (COLMAP: 30;
  // downscaled frames see a few dozen points of a young model).
  int initMinInliers = 100;
  int absPoseMinInliers = 15;
  // The largest share of a starting pair's motion that may lie along the view (COLMAP: 0.95).
  // Walking or driving footage moves mostly forward; at 0.95 the mapper skips every neighbouring
  // pair and on opensfm_lund built no model about half the time; at 0.999 it built one on all
  // the databases where it had failed.
  double initMaxForwardMotion = 0.999;
  // The mapper's start is randomized (RANSAC); on weak footage one seed builds a model and the
  // next builds none. A run without a model is retried with the next seed, up to this many runs.
  int mapperAttempts = 4;
  int firstMapperSeed = 0;  // the mapper's seeds are firstMapperSeed, +1, ...
  // Run the mapper again on the workspace's database (features and matches kept, the log
  // appended to): another seed after a model that was built but is wrong.
  bool remapOnly = false;
  // With initialFocalPx: the mapper holds the focal length and distortion fixed, and one bundle
  // adjustment frees them afterwards. Refining them while mapping, COLMAP settled on a sixth of
  // the focal length on frames 5 cm apart and built no model from 16 frames of 320x180 of the
  // synthetic walk (the first pair's points were wrong and no third frame registered); held, it
  // mapped all 16 in 3 s.
  bool fixIntrinsicsWhileMapping = true;
  // The freed focal length is kept only within this factor of initialFocalPx.
  double maxFocalRefinementRatio = 1.5;
  int threads = -1;  // -1: all cores
  // The program to run; empty uses $PLUVIA_COLMAP, else "colmap" on PATH.
  std::string colmapBinary;
};

struct ColmapRun {
  // <workspace>/model: the TXT model of the largest reconstruction (its intrinsics refined when
  // the mapper held them and the refinement was kept).
  std::filesystem::path modelFolder;
  std::filesystem::path logPath;  // <workspace>/colmap.log
  int modelCount = 0;             // how many disconnected models the mapper made
  double seconds = 0.0;           // wall time of the steps
  // The freed focal length over the starting one when that refinement was kept, else 1.
  double focalRefinementRatio = 1.0;
  bool intrinsicsHeldWhileMapping = false;  // the mapper held the starting intrinsics
};

// The COLMAP program to run when a request names none (the front end sets it from
// $PLUVIA_COLMAP, cli/process_variables.h, before any work); empty: "colmap" on PATH.
void setColmapProgram(const std::string& program);
// The program a request runs (request field, else the one set, else "colmap").
std::string colmapProgram(const std::string& requested = "");
// True when that program is found (a path that exists, or a name on PATH).
bool colmapAvailable(const std::string& requested = "");

// Runs the four steps; each appends its command line and output to <workspace>/colmap.log.
// Throws pluvia::Error naming the step and the log when a step fails or the mapper builds no
// model (typically too little parallax or texture).
ColmapRun runColmapSparse(const ColmapRequest& request);

}  // namespace pluvia::sfm
