// Depth: per-frame z-depth in metres for the rain's depth test and the fog, from
//  - "auto" (the default): a guess safe on any plate (stages/depth_guess.h): sky found in the
//    plate at infinity, the ground under the preset's camera, everything else at
//    depth.backdrop_m;
//  - "layers": manual layers (geometry/depth_layers.h: ground plane from the camera of the frame,
//    cards, polygons, sky), whose numbers and polygon points may be keyframed;
//  - "colmap": the clip tracked by COLMAP (stages/depth_tracking.h, cached per clip), each
//    frame's sparse points densified guided by the frame; the tracked camera path then drives
//    the rain camera (ClipContext::cameraPath). When tracking fails, depth.fallback = "layers"
//    falls back to the manual layers with a warning; otherwise the render stops before any frame;
//  - "file": the user's depth sequence (io/depth_sequence.h), depth.file's frame N for plate
//    frame N, decoded by depth.file_encoding and resampled to the plate;
//  - "none": everything at infinity (sky).
#include <filesystem>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "geometry/depth_layers.h"
#include "io/depth_sequence.h"
#include "pipeline/camera_settings.h"
#include "pipeline/plate_lens.h"
#include "stages/clip_still.h"
#include "stages/depth_guess.h"
#include "stages/depth_settings.h"
#include "stages/depth_tracking.h"
#include "stages/frame_sky.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/log.h"

namespace pluvia {
namespace {

// The guess takes each frame's own sky when more than this share of a frame shows something else
// than the clip's still (stillMismatch): people passing a locked-off camera change a few per
// cent; a pan or a walk, most of the frame.
constexpr double kMaxStillMismatch = 0.15;

// depth.source = "file": the sequence and how to decode it. An empty depth.file is refused here,
// when the render builds its stages, before anything is read or written; errors name the preset
// file `presetSource`.
DepthSequence depthSequence(const DepthSettings& depth, const std::string& presetSource) {
  if (depth.file.empty())
    throw Error(
        "depth.source is \"file\" but depth.file is empty: give the depth sequence "
        "(e.g. depth.####.exr) or one depth file for every frame",
        {"depth", {}, presetSource});
  DepthDecoding decoding;
  decoding.encoding = depthEncodingFromName(depth.fileEncoding);
  decoding.scale = depth.fileScale;
  decoding.nearMeters = depth.fileNearMeters;
  decoding.farMeters = depth.fileFarMeters;
  if (decoding.encoding == DepthEncoding::Normalized && decoding.farMeters <= decoding.nearMeters)
    throw Error(fmt::format("depth.file_far_m ({:g}) must be beyond depth.file_near_m ({:g})",
                            decoding.farMeters, decoding.nearMeters),
                {"depth", {}, presetSource});
  return DepthSequence(depth.file, decoding);
}

class DepthStage : public Stage {
 public:
  // `presetSource`: the preset file, named by errors in depth.file's settings.
  DepthStage(DepthSettings depth, CameraSettings camera, const std::string& presetSource)
      : depth_(std::move(depth)), camera_(std::move(camera)), dense_(depth_.colmapDense) {
    if (depth_.source == DepthSource::File) file_ = depthSequence(depth_, presetSource);
  }

  void prepare(ClipContext& clip) override {
    camera_ = withPlateLens(camera_, clip.plateLens);  // COLMAP starts from the plate's view
    prepareSource(clip);
    clip.firstFrameDepth = [this, &clip] { return firstFrameDepth(clip); };
  }
  void prepareSource(ClipContext& clip) {
    if (file_) {
      prepareFile(clip);
      return;
    }
    if (depth_.source == DepthSource::Colmap && prepareTracking(clip)) return;
    if (depth_.source == DepthSource::None) {
      depthMeters_.assign(static_cast<size_t>(clip.camera.width) * clip.camera.height,
                          std::numeric_limits<float>::infinity());
      return;
    }
    path_ = camera_.path(clip.camera);
    if (depth_.source == DepthSource::Auto) {
      prepareGuess(clip);
      return;
    }
    // Rasterising a frame costs a pass over every pixel per layer: do it once unless a layer moves
    // or the ground is seen from a moving camera (long clips would pay it on every frame).
    const nlohmann::json& layers = depth_.layers;
    perFrame_ = depthLayersAnimated(layers) || (path_.moving() && depthLayersHaveGround(layers));
    if (!perFrame_)
      depthMeters_ = rasterizeDepthLayers(path_.cameraAt(0.0), layers, 0.0, rampValueAt);
  }

  // What process() gives the clip's first frame (for the lamps found in the still).
  std::vector<float> firstFrameDepth(ClipContext& clip) {
    const int64_t first = clip.clip->frames.front();
    if (file_ && !file_->singleFile())
      return file_->read(first, clip.camera.width, clip.camera.height);
    if (sfm_) return sfm::colmapFrameDepth(*sfm_, first, clip.readWorking(first), dense_);
    if (perFrame_)
      return rasterizeDepthLayers(path_.cameraAt(double(first)), depth_.layers, double(first),
                                  rampValueAt);
    if (frameSky_) return guessOfFrame(clip, first, clip.readWorking(first));
    return depthMeters_;
  }

  void process(ClipContext& clip, FrameContext& frame) override {
    if (file_ && !file_->singleFile()) {
      frame.image.planes[kDepthPlane] =
          file_->read(frame.frame, frame.image.width, frame.image.height);
      return;
    }
    if (sfm_) {
      frame.image.planes[kDepthPlane] =
          sfm::colmapFrameDepth(*sfm_, frame.frame, frame.image, dense_);
      return;
    }
    if (perFrame_) {
      const double at = static_cast<double>(frame.frame);
      depthMeters_ = rasterizeDepthLayers(path_.cameraAt(at), depth_.layers, at, rampValueAt);
    }
    if (frameSky_) depthMeters_ = guessOfFrame(clip, frame.frame, frame.image);
    frame.image.planes[kDepthPlane] = depthMeters_;
  }

 private:
  static double rampValueAt(const nlohmann::json& value, double frame) {
    return Ramp::fromJson(value).valueAt(frame);
  }

  // Over the whole clip, not the frames this process renders, so that chunks agree. The sky is
  // the still's (rain and passers-by left out) unless the camera moves: then the still is a
  // blend of views, its sky no frame's (holes in a roof, sky cut off), and each frame's own sky
  // is found in it.
  void prepareGuess(ClipContext& clip) {
    const double mismatch = stillMismatch(clip);
    if (mismatch > kMaxStillMismatch) {
      frameSky_.emplace([this](double at) { return path_.cameraAt(at); });
      log::info(fmt::format(
          "depth: guessed from each frame (its own sky, voted with the frames beside it, ground "
          "under the camera, the rest at {:g} m): the camera moves ({:.0f} % of a frame shows "
          "something else than the clip's still); give depth.layers, a depth file or COLMAP for "
          "a better one",
          depth_.backdropMeters, 100.0 * mismatch));
      return;
    }
    const Camera camera = path_.cameraAt(0.0);
    DepthGuess guess = guessDepth(clipSky(clip, camera), camera, depth_.backdropMeters);
    log::info(fmt::format(
        "depth: guessed from the plate ({:.0f} % sky, {:.0f} % ground, the rest at {:g} m); "
        "give depth.layers, a depth file or COLMAP for a better one",
        100.0 * guess.skyFraction, 100.0 * guess.groundFraction, depth_.backdropMeters));
    depthMeters_ = std::move(guess.depthMeters);
  }

  std::vector<float> guessOfFrame(ClipContext& clip, int64_t frame, const Image& image) {
    return guessDepth(frameSky_->at(clip, frame, image), path_.cameraAt(double(frame)),
                      depth_.backdropMeters)
        .depthMeters;
  }

  // Every plate frame's depth file must exist before the first frame renders. The whole clip
  // is checked, not only the frames this render covers: ClipContext does not list those.
  void prepareFile(ClipContext& clip) {
    file_->requireFrames(clip.clip->frames);
    if (file_->singleFile())
      depthMeters_ = file_->read(clip.clip->frames.front(), clip.camera.width, clip.camera.height);
  }

  // The COLMAP source; false when it failed and depth.fallback sends the stage to the layers.
  bool prepareTracking(ClipContext& clip) {
    if (!dense_.empty() && !std::filesystem::is_directory(dense_ / "stereo" / "depth_maps"))
      throw Error(fmt::format("depth.colmap_dense: {} has no stereo/depth_maps folder (a COLMAP "
                              "dense workspace after patch_match_stereo)",
                              dense_.string()),
                  {"depth", {}, dense_.string()});
    try {
      sfm_ = trackedClipReconstruction(clip, depth_, camera_);
    } catch (const Error& e) {
      if (depth_.fallback != DepthFallback::Layers)
        throw Error(fmt::format("{}; set depth.fallback to \"layers\" (or depth.source to "
                                "\"layers\") to render this clip with the manual depth layers",
                                e.what()),
                    e.context());
      log::warning(fmt::format("depth: {}; using the manual depth layers (depth.fallback = layers)",
                               e.what()));
      return false;
    }
    if (!camera_.pathKeys.empty())
      log::warning("depth: the COLMAP-tracked camera replaces camera.path");
    clip.cameraPath = sfm_->path;
    clip.cameraTracked = true;
    return true;
  }

  DepthSettings depth_;
  CameraSettings camera_;
  std::filesystem::path dense_;
  std::optional<sfm::SfmReconstruction> sfm_;
  std::optional<DepthSequence> file_;
  CameraPath path_;
  bool perFrame_ = false;
  std::optional<FrameSky> frameSky_;  // the guess, with each frame's own sky (a moving camera)
  std::vector<float> depthMeters_;    // a frame's depth, when it is not made per frame
};

}  // namespace

StageInfo depthStageInfo() {
  return makeStageInfo(
      depthTable().section(), depthSettings,
      {.note = [](const DepthSettings& depth, const Preset&) -> std::string {
         if (depth.source == DepthSource::File)
           return fmt::format("depth from depth.file = {} ({})", depth.file, depth.fileEncoding);
         if (depth.source != DepthSource::Auto) return "";
         return fmt::format(
             "depth is a guess (sky found in the plate, ground under the camera, the rest at {:g} "
             "m): for a better one give depth.layers (source layers), a depth sequence (source "
             "file) or COLMAP tracking (source colmap)",
             depth.backdropMeters);
       },
       // The guess reads the sky in the still; tracking replaces the camera.
       .reads =
           [](const DepthSettings& depth, const Preset&) {
             return depth.source == DepthSource::Auto ? std::vector<std::string>{"still"}
                                                      : std::vector<std::string>{};
           },
       .writes =
           [](const DepthSettings& depth, const Preset&) {
             std::vector<std::string> writes{"depth", "first_frame_depth"};
             if (depth.source == DepthSource::Colmap) writes.push_back("camera");
             return writes;
           },
       .cacheKey =
           [](const DepthSettings& depth, const Preset& p, const ClipInfo& clip) {
             return depthTrackingCacheKey(depth, cameraSettings(p), clip);
           },
       .cachedWork =
           [](const DepthSettings& depth, const Preset&, const ClipInfo&,
              const std::string& framesKey, const ArtifactCache& cache) {
             return depth.source == DepthSource::Auto ? cachedStillNote(framesKey, cache)
                                                      : std::string();
           },
       .create =
           [](const DepthSettings& depth, const Preset& p) {
             return std::make_unique<DepthStage>(depth, cameraSettings(p), p.source());
           }});
}

}  // namespace pluvia
