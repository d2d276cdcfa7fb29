#pragma once
// The depth stage's COLMAP source: its settings from the preset, its cache key, and the tracked
// reconstruction of the clip (from the cache, or computed and stored there).
#include <string>

#include "pipeline/camera_settings.h"
#include "pipeline/stage.h"
#include "sfm/clip_tracking.h"
#include "stages/depth_settings.h"

namespace pluvia {

// depth.frame_step, depth.max_frames, depth.colmap_image_px, the scale hint (depth.scale) and the
// camera's field of view. The workspace is left for the caller to choose.
sfm::ClipTrackingSettings depthTrackingSettings(const DepthSettings& depth,
                                                const CameraSettings& camera);

// Hash of what the tracking depends on: the clip, those settings, pluvia's version. Empty when
// depth.source is not "colmap" or the model is given (depth.colmap_model).
std::string depthTrackingCacheKey(const DepthSettings& depth, const CameraSettings& camera,
                                  const ClipInfo& clip);

// The clip's reconstruction over all its frames (so that chunks of a farm render share one).
// From depth.colmap_model when given; else from the cache when it holds one; else COLMAP runs in a
// workspace of its own (in the cache folder, else the system's temporary folder), removed after
// success and kept, with its log, after a failure. Throws pluvia::Error naming the COLMAP log when
// COLMAP fails.
sfm::SfmReconstruction trackedClipReconstruction(ClipContext& clip, const DepthSettings& depth,
                                                 const CameraSettings& camera);

}  // namespace pluvia
