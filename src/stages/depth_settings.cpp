#include "stages/depth_settings.h"

namespace pluvia {

namespace {

// The depth.layers list: the fields of each layer type.
ParamSpec layersParam() {
  std::vector<ParamSpec> rect{fractionParam("x0", 0, "left edge, fraction of the width"),
                              fractionParam("x1", 1, "right edge, fraction of the width"),
                              fractionParam("y0", 0, "top edge, fraction of the height"),
                              fractionParam("y1", 1, "bottom edge, fraction of the height")};
  allowKeyframes(rect, {"x0", "x1", "y0", "y1"});
  std::vector<ParamSpec> card = rect;
  card.push_back(numberParam("distance_m", 10, {0.01, 1e6}, "m", "z-depth of the card"));
  allowKeyframes(card, {"distance_m"});
  // Points may lie outside the image (a road that runs out of frame): fractions in [-1, 2].
  const NumberRange pointRange{-1, 2};
  std::vector<ParamSpec> polygon{
      required(pointsParam("points", pointRange,
                           "polygon corners [[x, y], ...] as fractions of width/height (even-odd "
                           "fill at pixel centres), or keys [{\"frame\": F, \"points\": [...]}, "
                           "...] (linear between keys)")),
      numberParam("depth_m", 10, {0.01, 1e6}, "m",
                  "z-depth (at the top when depth_bottom_m is given)"),
      // Absent: a constant depth.
      withoutDefault(
          numberParam("depth_bottom_m", 0, {0.01, 1e6}, "m",
                      "optional: z-depth at the bottom, linear per row from depth_m at the top"))};
  allowKeyframes(polygon, {"depth_m", "depth_bottom_m"});
  std::vector<ParamSpec> sky = rect;
  sky.push_back(pointsParam("points", pointRange,
                            "optional polygon instead of the rectangle (as for \"polygon\")"));
  return listParam("layers", nlohmann::json::parse(R"([{"type":"ground"}])"),
                   {{"ground", {}}, {"card", card}, {"polygon", polygon}, {"sky", sky}},
                   "painted in order, each over the pixels it covers; uncovered pixels are sky");
}

}  // namespace

const SettingsTable<DepthSettings>& depthTable() {
  using S = DepthSettings;
  static const SettingsTable<DepthSettings> table(
      {.name = "depth",
       .help = "Scene depth per frame (metres) from manual layers (ground, card, polygon, sky), "
               "COLMAP structure from motion or a depth sequence of the plate (depth.file); sky is "
               "at infinity.",
       .inputs = {"still"},
       .outputs = {"depth", "camera", "first_frame_depth"}},
      {
          bind(&S::enabled, enabledParam()),
          bind(&S::source, "source",
               {{"auto", DepthSource::Auto},
                {"layers", DepthSource::Layers},
                {"colmap", DepthSource::Colmap},
                {"file", DepthSource::File},
                {"none", DepthSource::None}},
               "auto: a guess from the plate (sky at infinity, the ground under the camera, the "
               "rest at depth.backdrop_m); layers: depth.layers; colmap: COLMAP structure from "
               "motion of the clip (its camera also moves the rain); file: depth.file, a depth "
               "sequence frame-matched to the plate; none: all sky"),
          bind(&S::layers, layersParam()),
          bind(&S::backdropMeters,
               numberParam("backdrop_m", 20.0, {0.5, 1e5}, "m",
                           "auto: the distance of everything that is neither sky nor ground")),
          bind(&S::fallback, "fallback",
               {{"error", DepthFallback::Error}, {"layers", DepthFallback::Layers}},
               "colmap: when tracking fails (no colmap, no parallax, too few frames registered), "
               "stop (error) or use depth.layers (layers)"),
          bind(&S::frameStep,
               integerParam("frame_step", 0, {0, 1000}, "frames",
                            "colmap: every Nth frame is tracked; 0: frames chosen so that each "
                            "shows parallax against the one before; frames between interpolate")),
          bind(&S::maxFrames,
               integerParam("max_frames", 200, {3, 100000}, "frames",
                            "colmap: at most this many frames are tracked (thinned evenly)")),
          bind(&S::colmapImagePx,
               integerParam("colmap_image_px", 1600, {160, 10000}, "px",
                            "colmap: features are found on frames downscaled to this longest "
                            "side")),
          bind(&S::colmapModel,
               pathParam("colmap_model", "",
                         "colmap: a COLMAP text model of this clip (cameras.txt, images.txt, "
                         "points3D.txt) to read instead of running COLMAP; images named "
                         "frame_%08d.png (pluvia depth's) or as the clip's files")),
          bind(&S::colmapDense,
               pathParam("colmap_dense", "",
                         "colmap: a dense workspace of the same model (stereo/depth_maps after "
                         "patch_match_stereo); its depth maps replace the densified points where "
                         "they have estimates")),
          bind(&S::scale, "scale",
               {{"camera_height", DepthScale::CameraHeight},
                {"first_frame_depth", DepthScale::FirstFrameDepth}},
               "colmap: metric scale from camera.height_m over the fitted ground plane, or from "
               "depth.first_frame_depth_m"),
          bind(&S::firstFrameDepthMeters,
               numberParam("first_frame_depth_m", 10.0, {0.01, 1e6}, "m",
                           "colmap, scale first_frame_depth: median distance of what the first "
                           "frame sees")),
          bind(&S::file,
               pathParam("file", "",
                         "file: the depth sequence, depth.####.exr or depth.%04d.png (frame N "
                         "for plate frame N, a movie plate's frames counted from 0), or one "
                         "file for every frame; channel Z, depth.Z, Y or R, or the only one; "
                         "resampled to the plate size (bilinear on 1/z)")),
          bind(&S::fileEncoding,
               enumParam("file_encoding", "z_m", {"z_m", "inverse", "normalized"},
                         "file: what a value v means (8/16-bit files: v = code / max code, in "
                         "[0, 1]); z_m: z-depth = file_scale * v metres; inverse: z = file_scale "
                         "/ v (depth estimators); normalized: z = file_near_m + v * (file_far_m - "
                         "file_near_m); z <= 0, NaN, inf: sky")),
          bind(&S::fileScale,
               numberParam("file_scale", 1.0, {1e-9, 1e9}, "",
                           "file, z_m: metres per file unit; inverse: z = file_scale / v metres")),
          bind(&S::fileNearMeters, numberParam("file_near_m", 1.0, {0.0, 1e6}, "m",
                                               "file, normalized: z-depth at v = 0")),
          bind(&S::fileFarMeters, numberParam("file_far_m", 100.0, {0.01, 1e6}, "m",
                                              "file, normalized: z-depth at v = 1")),
      });
  return table;
}

DepthSettings depthSettings(const Preset& p) {
  return depthTable().read(p);
}

}  // namespace pluvia
