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

// 4: gravity from façade lines, sloping ground; 5: a model bent beyond use is refused (a cached
// one from before would be used).
constexpr const char* kTrackingVersion = "5";
constexpr const char* kCacheStage = "depth";

// The values the tracking depends on (not the layers or the fallback), by section and key: the
// JSON text of each as the preset gives it is hashed, so that a key does not change with how a
// number is written.
constexpr const char* kTrackingDepthKeys[] = {"frame_step", "max_frames", "colmap_image_px",
                                              "scale", "first_frame_depth_m"};
// lens_from_plate: whether the plate's stated view replaces fov_deg as COLMAP's start.
constexpr const char* kTrackingCameraKeys[] = {"fov_deg", "lens_from_plate", "height_m"};

}  // namespace

sfm::ClipTrackingSettings depthTrackingSettings(const DepthSettings& depth,
                                                const CameraSettings& camera) {
  sfm::ClipTrackingSettings settings;
  settings.frameStep = depth.frameStep;
  settings.maxFrames = depth.maxFrames;
  settings.horizontalFovDeg = camera.fovDeg;
  settings.maxImageSizePx = depth.colmapImagePx;
  if (depth.scale == DepthScale::CameraHeight)
    settings.sfm.scale.cameraHeightMeters = camera.heightMeters;
  else
    settings.sfm.scale.firstFrameMedianDepthMeters = depth.firstFrameDepthMeters;
  return settings;
}

std::string depthTrackingCacheKey(const DepthSettings& depth, const CameraSettings& camera,
                                  const ClipInfo& clip) {
  // A model given by depth.colmap_model is read, not computed: nothing to cache.
  if (depth.source != DepthSource::Colmap || !depth.colmapModel.empty()) return "";
  Hasher hasher;
  hasher.add("depth-colmap").add(kTrackingVersion).add(kVersion).add(clipIdentity(clip));
  for (const char* key : kTrackingDepthKeys)
    hasher.add(std::string("depth.") + key).add(depth.resolved.at(key).dump());
  for (const char* key : kTrackingCameraKeys)
    hasher.add(std::string("camera.") + key).add(camera.resolved.at(key).dump());
  return hasher.hex();
}

sfm::SfmReconstruction trackedClipReconstruction(ClipContext& clip, const DepthSettings& depth,
                                                 const CameraSettings& camera) {
  if (const std::string& model = depth.colmapModel; !model.empty()) {
    if (!std::filesystem::exists(std::filesystem::path(model) / "images.txt"))
      throw Error(
          fmt::format("depth.colmap_model: {} holds no COLMAP text model (images.txt)", model),
          {"depth", {}, model});
    const ClipInfo& info = *clip.clip;
    sfm::SfmReconstruction reconstruction = sfm::trackingFromModel(
        model, info.frames, info.isMovie ? std::vector<std::string>{} : info.files,
        depthTrackingSettings(depth, camera).sfm);
    if (!reconstruction.ok())
      throw Error(fmt::format("depth.colmap_model {}: {}", model, reconstruction.message),
                  {"depth", {}, model});
    log::info(fmt::format("depth: COLMAP model {}: {} of {} frames registered", model,
                          reconstruction.registeredCount, info.frames.size()));
    return reconstruction;
  }
  const std::string key = depthTrackingCacheKey(depth, camera, *clip.clip);
  if (clip.cache) {
    if (auto cached = clip.cache->load(kCacheStage, key)) {
      try {
        sfm::SfmReconstruction reconstruction = sfm::reconstructionFromJson(*cached);
        log::info(fmt::format("depth: COLMAP tracking from cache ({})",
                              clip.cache->pathFor(kCacheStage, key).string()));
        return reconstruction;
      } catch (const std::exception& e) {
        log::warning(fmt::format("depth: cached tracking {} is unreadable ({}); tracking again",
                                 clip.cache->pathFor(kCacheStage, key).string(), e.what()));
      }
    }
  }
  sfm::ClipTrackingSettings settings = depthTrackingSettings(depth, camera);
  // A movie's rate checks the scale (camera speed); a sequence's 24 fps is only a default.
  if (clip.clip->isMovie) settings.sfm.framesPerSecond = clip.clip->fps;
  // A workspace per process: farm chunks of one clip may track at the same time.
  const std::string folder = fmt::format("colmap-{}-{}", key, ::getpid());
  settings.workspace = clip.cache ? clip.cache->pathFor(kCacheStage, key).parent_path() / folder
                                  : std::filesystem::temp_directory_path() / ("pluvia-" + folder);
  const sfm::ClipTracking tracking = sfm::trackClip(
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
  if (clip.cache) clip.cache->store(kCacheStage, key, sfm::reconstructionToJson(tracking.sfm));
  std::error_code ignored;
  std::filesystem::remove_all(settings.workspace, ignored);
  return tracking.sfm;
}

}  // namespace pluvia
