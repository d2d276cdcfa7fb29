#pragma once
// Camera tracking of a clip with COLMAP, and its per-frame depth: what the depth stage, `pluvia
// depth --source colmap` and `pluvia report depth` share.
//
// The clip's frames to track (every frameStep-th, or frames chosen so that each shows parallax
// against the one before: neighbouring video frames are too close for COLMAP's mapper to start
// from) are written as 8-bit PNGs to <workspace>/frames and handed to COLMAP (colmap_runner.h); the
// registered frames become keys of the camera path, and frames between keys get interpolated poses
// (camera_path.h). A frame's depth densifies the sparse points the nearest registered frame
// observed (sparse_densify.h), guided by the frame itself.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "image/image.h"
#include "sfm/colmap_runner.h"
#include "sfm/sfm_poses.h"
#include "sfm/sparse_densify.h"

namespace pluvia::sfm {

struct ClipTrackingSettings {
  std::filesystem::path workspace;  // COLMAP's folder (frames/, images/, database, log)
  // Every Nth frame goes to COLMAP; 0 chooses them by parallax (parallax_check.h selectKeyframes).
  int frameStep = 0;
  int maxFrames = 200;    // at most this many go to COLMAP (evenly thinned)
  int minFrames = 12;     // frames chosen by parallax: at least this many (or all the clip's)
  int remapAttempts = 2;  // mapper reruns after no ground plane or an implausible focal length
  // A model that built but looks bent (scale_cues.h bentness above 1) is mapped again on one
  // thread with other seeds and the intrinsics the other way (refined while mapping if they were
  // held), at most this many times, until one is bent no more; the straightest is kept. 0: kept
  // as it is, warned.
  int bentRemaps = 3;
  double maxFocalRatio = 2.0;      // COLMAP's focal length within this factor of the preset's
  double horizontalFovDeg = 60.0;  // COLMAP's starting focal length
  int maxImageSizePx = 1600;       // SIFT on frames downscaled to this longest side
  std::string colmapBinary;        // empty: $PLUVIA_COLMAP, else "colmap"
  SfmOptions sfm;                  // scale hint and fallback thresholds
};

struct ClipTracking {
  SfmReconstruction sfm;
  ColmapRun run;
  std::vector<int64_t> framesUsed;  // handed to COLMAP
  double seconds = 0.0;             // frame export and COLMAP
};

// Of two models of the same clip, the one to keep: `second` (a remap of a bent `first`) only when
// it built with status Ok and is clearly straighter (bentness under 0.8 of the first's); `why`
// gets the two bentness figures and the choice.
bool keepSecondModel(const SfmReconstruction& first, const SfmReconstruction& second,
                     const SfmOptions& options, std::string& why);

// Each remap of a bent model writes its own <workspace>/model: the folder of the model kept so
// far is moved to <workspace>/model.kept before it, and afterwards the folder of the model kept
// now (remapped: the remap's) is left as <workspace>/model and the other removed, so that folder,
// which depth.colmap_model reads and the log points users at, always holds the model used
// (before, it held the remap's model even when the first was kept).
void setKeptModelAside(const std::filesystem::path& workspace);
void keepModelFolder(const std::filesystem::path& workspace, bool remapped);

// A model that stays bent past SfmOptions::maxUsableBentness (after the remap) gets status Bent
// and a message naming why, so the depth stage stops (or falls back to the layers) instead of
// rendering with its scale and depth.
void refuseUnusableModel(SfmReconstruction& sfm, const SfmOptions& options);

// Every step-th of `frames` from the first, and the last.
std::vector<int64_t> trackingFrames(const std::vector<int64_t>& frames, int step);

// Runs COLMAP on the clip's frames and builds the metric reconstruction. `readFrame` returns a
// frame with display-referred values in 0..1 (what a PNG holds). Throws pluvia::Error naming the
// COLMAP step and log when COLMAP fails; a weak reconstruction is returned with its status.
ClipTracking trackClip(const std::vector<int64_t>& frames,
                       const std::function<Image(int64_t)>& readFrame,
                       const ClipTrackingSettings& settings);

// The clip's tracking from a COLMAP text model made beforehand (by an earlier `pluvia depth`, or
// by the user's own COLMAP run): no COLMAP runs. Images are frames by name: pluvia's own
// "frame_%08d.png" when the model has such names, else, for an image sequence, the file name of
// each frame (`files` parallel to `frames`; empty for a movie).
SfmReconstruction trackingFromModel(const std::filesystem::path& textModelFolder,
                                    const std::vector<int64_t>& frames,
                                    const std::vector<std::string>& files,
                                    const SfmOptions& options);

// The frame's depth from a dense COLMAP workspace (<denseWorkspace>/stereo/depth_maps, made by
// patch_match_stereo from the same model), metric, resized to width x height (nearest: the
// undistorted image may differ slightly in size); pixels without an estimate are NaN. Nothing
// when the frame is not a registered image or its map is missing.
std::optional<std::vector<float>> denseFrameDepth(const SfmReconstruction& sfm,
                                                  const std::filesystem::path& denseWorkspace,
                                                  int64_t frame, int width, int height);

// The frame's metric z-depth (+inf for sky), width * height row-major, `image` its guide.
std::vector<float> trackedFrameDepth(const SfmReconstruction& sfm, int64_t frame,
                                     const Image& image, const DensifyOptions& options = {});

// The depth the depth stage uses: the dense map (denseFrameDepth) where `denseWorkspace` is given
// and has one for the frame, its holes filled by trackedFrameDepth; else trackedFrameDepth.
std::vector<float> colmapFrameDepth(const SfmReconstruction& sfm, int64_t frame, const Image& image,
                                    const std::filesystem::path& denseWorkspace);

// The reconstruction as JSON (the depth cache) and back. The JSON keeps what the depth and rain
// stages use: status, message, statistics, intrinsics, keyframes (pose, visible points) and points.
nlohmann::json reconstructionToJson(const SfmReconstruction& sfm);
SfmReconstruction reconstructionFromJson(const nlohmann::json& json);

// The poses of `frames` for users (`pluvia depth` writes it as poses.json).
nlohmann::json posesJson(const SfmReconstruction& sfm, const std::vector<int64_t>& frames);

}  // namespace pluvia::sfm
