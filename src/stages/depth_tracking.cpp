#include "stages/depth_tracking.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "pipeline/cache.h"
#include "pluvia/version.h"
#include "util/error.h"
#include "util/hash.h"
#include "util/log.h"

namespace pluvia {
namespace {

constexpr const char* kTrackingVersion = "4";  // 4: gravity from façade lines, sloping ground
constexpr const char* kCacheStage = "depth";

// The preset keys the tracking depends on (not the layers or the fallback).
constexpr const char* kTrackingKeys[] = {
    "depth.frame_step",          "depth.max_frames", "depth.colmap_image_px", "depth.scale",
    "depth.first_frame_depth_m", "camera.fov_deg",   "camera.height_m"};

}  // namespace

ClipTrackingSettings depthTrackingSettings(const Preset& preset) {
  ClipTrackingSettings settings;
  settings.frameStep = static_cast<int>(preset.number("depth.frame_step"));
  settings.maxFrames = static_cast<int>(preset.number("depth.max_frames"));
  settings.horizontalFovDeg = preset.number("camera.fov_deg");
  settings.maxImageSizePx = static_cast<int>(preset.number("depth.colmap_image_px"));
  if (preset.string("depth.scale") == "camera_height")
    settings.sfm.scale.cameraHeightMeters = preset.number("camera.height_m");
  else
    settings.sfm.scale.firstFrameMedianDepthMeters = preset.number("depth.first_frame_depth_m");
  return settings;
}

std::string depthTrackingCacheKey(const Preset& preset, const ClipInfo& clip) {
  // A model given by depth.colmap_model is read, not computed: nothing to cache.
  if (preset.string("depth.source") != "colmap" || !preset.string("depth.colmap_model").empty())
    return "";
  Hasher hasher;
  hasher.add("depth-colmap").add(kTrackingVersion).add(kVersion).add(clipIdentity(clip));
  for (const char* key : kTrackingKeys) hasher.add(key).add(preset.at(key).dump());
  return hasher.hex();
}

SfmReconstruction trackedClipReconstruction(ClipContext& clip) {
  const Preset& preset = *clip.preset;
  if (const std::string model = preset.string("depth.colmap_model"); !model.empty()) {
    if (!std::filesystem::exists(std::filesystem::path(model) / "images.txt"))
      throw Error(
          fmt::format("depth.colmap_model: {} holds no COLMAP text model (images.txt)", model),
          {"depth", {}, model});
    const ClipInfo& info = *clip.clip;
    SfmReconstruction sfm = trackingFromModel(
        model, info.frames, info.isMovie ? std::vector<std::string>{} : info.files,
        depthTrackingSettings(preset).sfm);
    if (!sfm.ok())
      throw Error(fmt::format("depth.colmap_model {}: {}", model, sfm.message),
                  {"depth", {}, model});
    log::info(fmt::format("depth: COLMAP model {}: {} of {} frames registered", model,
                          sfm.registeredCount, info.frames.size()));
    return sfm;
  }
  const std::string key = depthTrackingCacheKey(preset, *clip.clip);
  if (clip.cache) {
    if (auto cached = clip.cache->load(kCacheStage, key)) {
      try {
        SfmReconstruction sfm = reconstructionFromJson(*cached);
        log::info(fmt::format("depth: COLMAP tracking from cache ({})",
                              clip.cache->pathFor(kCacheStage, key).string()));
        return sfm;
      } catch (const std::exception& e) {
        log::warning(fmt::format("depth: cached tracking {} is unreadable ({}); tracking again",
                                 clip.cache->pathFor(kCacheStage, key).string(), e.what()));
      }
    }
  }
  ClipTrackingSettings settings = depthTrackingSettings(preset);
  // A movie's rate checks the scale (camera speed); a sequence's 24 fps is only a default.
  if (clip.clip->isMovie) settings.sfm.framesPerSecond = clip.clip->fps;
  // A workspace per process: farm chunks of one clip may track at the same time.
  const std::string folder = fmt::format("colmap-{}-{}", key, ::getpid());
  settings.workspace = clip.cache ? clip.cache->pathFor(kCacheStage, key).parent_path() / folder
                                  : std::filesystem::temp_directory_path() / ("pluvia-" + folder);
  const ClipTracking tracking = trackClip(
      clip.clip->frames, [&clip](int64_t frame) { return clip.reader->read(frame); }, settings);
  if (!tracking.run.logPath.empty())
    log::info(fmt::format(
        "depth: COLMAP registered {} of {} frames in {:.0f} s, {:.2f} px mean reprojection "
        "error, focal length {:.1f} px{}",
        tracking.sfm.registeredCount, tracking.sfm.frameCount, tracking.seconds,
        tracking.sfm.meanReprojectionErrorPx, tracking.sfm.intrinsics.focalPx,
        tracking.sfm.message.empty() ? "" : "; " + tracking.sfm.message));
  if (!tracking.sfm.ok()) {
    // Kept, with the log, for the user to look at.
    const std::string log = tracking.run.logPath.empty()
                                ? std::string()
                                : " (COLMAP log: " + tracking.run.logPath.string() + ")";
    throw Error(fmt::format("{}: {}{}", clip.clip->path, tracking.sfm.message, log),
                {"depth", {}, clip.clip->path});
  }
  if (clip.cache) clip.cache->store(kCacheStage, key, reconstructionToJson(tracking.sfm));
  std::error_code ignored;
  std::filesystem::remove_all(settings.workspace, ignored);
  return tracking.sfm;
}

}  // namespace pluvia
