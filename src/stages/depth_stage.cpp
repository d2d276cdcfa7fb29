// Depth: per-frame z-depth in metres for the rain's depth test and the fog, from
//  - "auto" (the default): a guess safe on any plate (stages/depth_guess.h): sky found in the
//    plate at infinity, the ground under the preset's camera, everything else at
//    depth.backdrop_m;
//  - "layers": manual layers (geometry/depth_layers.h: ground plane from the camera of the frame,
//    cards, polygons, sky), whose numbers and polygon points may be keyframed;
//  - "colmap": the clip tracked by COLMAP (stages/depth_tracking.h, cached per clip), each
//    frame's sparse points densified guided by the frame; the tracked camera path then drives
//    the rain camera (ClipContext::trackedPath). When tracking fails, depth.fallback = "layers"
//    falls back to the manual layers with a warning; otherwise the render stops before any frame;
//  - "file": the user's depth sequence (io/depth_sequence.h), depth.file's frame N for plate
//    frame N, decoded by depth.file_encoding and resampled to the plate;
//  - "none": everything at infinity (sky).
#include <filesystem>
#include <limits>

#include <fmt/format.h>

#include "geometry/depth_layers.h"
#include "io/depth_sequence.h"
#include "preset/camera_path_preset.h"
#include "stages/clip_still.h"
#include "stages/depth_guess.h"
#include "stages/depth_tracking.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/log.h"

namespace pluvia {
namespace {

bool hasGroundLayer(const nlohmann::json& layers) {
  for (const auto& layer : layers)
    if (layer.value("type", "") == "ground") return true;
  return false;
}

// depth.source = "file": the sequence and how to decode it. An empty depth.file is refused here,
// when the render builds its stages, before anything is read or written.
DepthSequence depthSequenceFromPreset(const Preset& p) {
  const std::string file = p.string("depth.file");
  if (file.empty())
    throw Error(
        "depth.source is \"file\" but depth.file is empty: give the depth sequence "
        "(e.g. depth.####.exr) or one depth file for every frame",
        {"depth", {}, p.source()});
  DepthDecoding decoding;
  decoding.encoding = depthEncodingFromName(p.string("depth.file_encoding"));
  decoding.scale = p.number("depth.file_scale");
  decoding.nearMeters = p.number("depth.file_near_m");
  decoding.farMeters = p.number("depth.file_far_m");
  if (decoding.encoding == DepthEncoding::Normalized && decoding.farMeters <= decoding.nearMeters)
    throw Error(fmt::format("depth.file_far_m ({:g}) must be beyond depth.file_near_m ({:g})",
                            decoding.farMeters, decoding.nearMeters),
                {"depth", {}, p.source()});
  return DepthSequence(file, decoding);
}

class DepthStage : public Stage {
 public:
  explicit DepthStage(const Preset& p)
      : source_(p.string("depth.source")),
        fallback_(p.string("depth.fallback")),
        dense_(p.string("depth.colmap_dense")),
        layers_(p.at("depth.layers")),
        backdropMeters_(p.number("depth.backdrop_m")) {
    if (source_ == "file") file_ = depthSequenceFromPreset(p);
  }

  void prepare(ClipContext& clip) override {
    if (file_) {
      prepareFile(clip);
      return;
    }
    if (source_ == "colmap" && prepareTracking(clip)) return;
    if (source_ == "none") {
      depth_.assign(static_cast<size_t>(clip.camera.width) * clip.camera.height,
                    std::numeric_limits<float>::infinity());
      return;
    }
    path_ = clip.preset ? cameraPathFromPreset(*clip.preset, clip.camera)
                        : CameraPath::fixed(clip.camera);
    if (source_ == "auto") {
      prepareGuess(clip);
      return;
    }
    // Rasterising a frame costs a pass over every pixel per layer: do it once unless a layer moves
    // or the ground is seen from a moving camera (long clips would pay it on every frame).
    perFrame_ = depthLayersAnimated(layers_) || (path_.moving() && hasGroundLayer(layers_));
    if (!perFrame_) depth_ = rasterizeDepthLayers(path_.cameraAt(0.0), layers_, 0.0, rampValueAt);
  }
  void process(ClipContext&, FrameContext& frame) override {
    if (file_ && !file_->singleFile()) {
      frame.image.planes["depth"] = file_->read(frame.frame, frame.image.width, frame.image.height);
      return;
    }
    if (sfm_) {
      frame.image.planes["depth"] = colmapFrameDepth(*sfm_, frame.frame, frame.image, dense_);
      return;
    }
    if (perFrame_) {
      const double at = static_cast<double>(frame.frame);
      depth_ = rasterizeDepthLayers(path_.cameraAt(at), layers_, at, rampValueAt);
    }
    frame.image.planes["depth"] = depth_;
  }

 private:
  static double rampValueAt(const nlohmann::json& value, double frame) {
    return Ramp::fromJson(value).valueAt(frame);
  }

  // Over the whole clip, not the frames this process renders, so that chunks agree.
  void prepareGuess(ClipContext& clip) {
    const Camera camera = path_.cameraAt(0.0);
    DepthGuess guess = guessDepth(clipSky(clip, camera), camera, backdropMeters_);
    log::info(fmt::format(
        "depth: guessed from the plate ({:.0f} % sky, {:.0f} % ground, the rest at {:g} m); "
        "give depth.layers, a depth file or COLMAP for a better one",
        100.0 * guess.skyFraction, 100.0 * guess.groundFraction, backdropMeters_));
    depth_ = std::move(guess.depthMeters);
  }

  // Every plate frame's depth file must exist before the first frame renders. The whole clip
  // is checked, not only the frames this render covers: ClipContext does not list those.
  void prepareFile(ClipContext& clip) {
    file_->requireFrames(clip.clip->frames);
    if (file_->singleFile())
      depth_ = file_->read(clip.clip->frames.front(), clip.camera.width, clip.camera.height);
  }

  // The COLMAP source; false when it failed and depth.fallback sends the stage to the layers.
  bool prepareTracking(ClipContext& clip) {
    if (!dense_.empty() && !std::filesystem::is_directory(dense_ / "stereo" / "depth_maps"))
      throw Error(fmt::format("depth.colmap_dense: {} has no stereo/depth_maps folder (a COLMAP "
                              "dense workspace after patch_match_stereo)",
                              dense_.string()),
                  {"depth", {}, dense_.string()});
    try {
      sfm_ = trackedClipReconstruction(clip);
    } catch (const Error& e) {
      if (fallback_ != "layers")
        throw Error(fmt::format("{}; set depth.fallback to \"layers\" (or depth.source to "
                                "\"layers\") to render this clip with the manual depth layers",
                                e.what()),
                    e.context());
      log::warning(fmt::format("depth: {}; using the manual depth layers (depth.fallback = layers)",
                               e.what()));
      return false;
    }
    if (clip.preset && !clip.preset->at("camera.path").empty())
      log::warning("depth: the COLMAP-tracked camera replaces camera.path");
    clip.trackedPath = sfm_->path;
    return true;
  }

  std::string source_;
  std::string fallback_;
  std::filesystem::path dense_;
  std::optional<SfmReconstruction> sfm_;
  std::optional<DepthSequence> file_;
  nlohmann::json layers_;
  double backdropMeters_;
  CameraPath path_;
  bool perFrame_ = false;
  std::vector<float> depth_;
};

ParamSpec layerField(const std::string& key, double def, double lo, double hi,
                     const std::string& units, const std::string& help) {
  return {key, ParamType::Number, def, lo, hi, {}, units, help};
}

}  // namespace

StageInfo depthStageInfo() {
  StageInfo info;
  info.spec.name = "depth";
  info.spec.help =
      "Scene depth per frame (metres) from manual layers (ground, card, polygon, sky), COLMAP "
      "structure from motion or a depth sequence of the plate (depth.file); sky is at infinity.";
  info.spec.outputs = {"depth"};
  ParamSpec layers{"layers",
                   ParamType::List,
                   nlohmann::json::parse(R"([{"type":"ground"}])"),
                   {},
                   {},
                   {},
                   "",
                   "painted in order, each over the pixels it covers; uncovered pixels are sky"};
  std::vector<ParamSpec> rect{layerField("x0", 0, 0, 1, "", "left edge, fraction of the width"),
                              layerField("x1", 1, 0, 1, "", "right edge, fraction of the width"),
                              layerField("y0", 0, 0, 1, "", "top edge, fraction of the height"),
                              layerField("y1", 1, 0, 1, "", "bottom edge, fraction of the height")};
  allowKeyframes(rect, {"x0", "x1", "y0", "y1"});
  std::vector<ParamSpec> card = rect;
  card.push_back(layerField("distance_m", 10, 0.01, 1e6, "m", "z-depth of the card"));
  allowKeyframes(card, {"distance_m"});
  // Points may lie outside the image (a road that runs out of frame): fractions in [-1, 2].
  ParamSpec points{"points",
                   ParamType::Points2,
                   nullptr,
                   -1,
                   2,
                   {},
                   "",
                   "polygon corners [[x, y], ...] as fractions of width/height (even-odd fill at "
                   "pixel centres), "
                   "or keys [{\"frame\": F, \"points\": [...]}, ...] (linear between keys)"};
  std::vector<ParamSpec> polygon{
      points,
      layerField("depth_m", 10, 0.01, 1e6, "m",
                 "z-depth (at the top when depth_bottom_m is given)"),
      layerField("depth_bottom_m", 0, 0.01, 1e6, "m",
                 "optional: z-depth at the bottom, linear per row from depth_m at the top")};
  polygon[2].defaultValue = nullptr;  // absent: constant depth
  polygon[0].required = true;
  allowKeyframes(polygon, {"depth_m", "depth_bottom_m"});
  std::vector<ParamSpec> sky = rect;
  points.help = "optional polygon instead of the rectangle (as for \"polygon\")";
  sky.push_back(points);
  layers.itemTypes = {{"ground", {}}, {"card", card}, {"polygon", polygon}, {"sky", sky}};
  info.spec.params = {
      {"enabled", ParamType::Boolean, true, {}, {}, {}, "", "run this stage"},
      {"source",
       ParamType::Enum,
       "auto",
       {},
       {},
       {"auto", "layers", "colmap", "file", "none"},
       "",
       "auto: a guess from the plate (sky at infinity, the ground under the camera, the rest at "
       "depth.backdrop_m); layers: depth.layers; colmap: COLMAP structure from motion of the clip "
       "(its camera "
       "also moves the rain); file: depth.file, a depth sequence frame-matched to the plate; "
       "none: all sky"},
      layers,
      {"backdrop_m",
       ParamType::Number,
       20.0,
       0.5,
       1e5,
       {},
       "m",
       "auto: the distance of everything that is neither sky nor ground"},
      {"fallback",
       ParamType::Enum,
       "error",
       {},
       {},
       {"error", "layers"},
       "",
       "colmap: when tracking fails (no colmap, no parallax, too few frames registered), stop "
       "(error) or use depth.layers (layers)"},
      {"frame_step",
       ParamType::Integer,
       0,
       0,
       1000,
       {},
       "frames",
       "colmap: every Nth frame is tracked; 0: frames chosen so that each shows parallax against "
       "the one before; frames between interpolate"},
      {"max_frames",
       ParamType::Integer,
       200,
       3,
       100000,
       {},
       "frames",
       "colmap: at most this many frames are tracked (thinned evenly)"},
      {"colmap_image_px",
       ParamType::Integer,
       1600,
       160,
       10000,
       {},
       "px",
       "colmap: features are found on frames downscaled to this longest side"},
      {"colmap_model",
       ParamType::String,
       "",
       {},
       {},
       {},
       "",
       "colmap: a COLMAP text model of this clip (cameras.txt, images.txt, points3D.txt) to read "
       "instead of running COLMAP; images named frame_%08d.png (pluvia depth's) or as the clip's "
       "files"},
      {"colmap_dense",
       ParamType::String,
       "",
       {},
       {},
       {},
       "",
       "colmap: a dense workspace of the same model (stereo/depth_maps after patch_match_stereo); "
       "its depth maps replace the densified points where they have estimates"},
      {"scale",
       ParamType::Enum,
       "camera_height",
       {},
       {},
       {"camera_height", "first_frame_depth"},
       "",
       "colmap: metric scale from camera.height_m over the fitted ground plane, or from "
       "depth.first_frame_depth_m"},
      {"first_frame_depth_m",
       ParamType::Number,
       10.0,
       0.01,
       1e6,
       {},
       "m",
       "colmap, scale first_frame_depth: median distance of what the first frame sees"},
      {"file",
       ParamType::String,
       "",
       {},
       {},
       {},
       "",
       "file: the depth sequence, depth.####.exr or depth.%04d.png (frame N for plate frame N, "
       "a movie plate's frames counted from 0), or one file for every frame; channel Z, "
       "depth.Z, Y or R, or the only one; resampled to the plate size (bilinear on 1/z)"},
      {"file_encoding",
       ParamType::Enum,
       "z_m",
       {},
       {},
       {"z_m", "inverse", "normalized"},
       "",
       "file: what a value v means (8/16-bit files: v = code / max code, in [0, 1]); z_m: "
       "z-depth = file_scale * v metres; inverse: z = file_scale / v (depth estimators); "
       "normalized: z = file_near_m + v * (file_far_m - file_near_m); z <= 0, NaN, inf: sky"},
      {"file_scale",
       ParamType::Number,
       1.0,
       1e-9,
       1e9,
       {},
       "",
       "file, z_m: metres per file unit; inverse: z = file_scale / v metres"},
      {"file_near_m",
       ParamType::Number,
       1.0,
       0.0,
       1e6,
       {},
       "m",
       "file, normalized: z-depth at v = 0"},
      {"file_far_m",
       ParamType::Number,
       100.0,
       0.01,
       1e6,
       {},
       "m",
       "file, normalized: z-depth at v = 1"},
  };
  info.note = [](const Preset& p) -> std::string {
    if (p.string("depth.source") == "file")
      return fmt::format("depth from depth.file = {} ({})", p.string("depth.file"),
                         p.string("depth.file_encoding"));
    if (p.string("depth.source") != "auto") return "";
    return fmt::format(
        "depth is a guess (sky found in the plate, ground under the camera, the rest at {:g} m): "
        "for a better one give depth.layers (source layers), a depth sequence (source file) or "
        "COLMAP tracking (source colmap)",
        p.number("depth.backdrop_m"));
  };
  info.cacheKey = depthTrackingCacheKey;
  info.create = [](const Preset& p) { return std::make_unique<DepthStage>(p); };
  return info;
}

}  // namespace pluvia
