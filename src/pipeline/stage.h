#pragma once
// The Stage interface and the data a stage declares about itself (FFmpeg AVFilter style):
// its section of the preset (parameter table, reads, writes), when it is a no-op, and how to
// build it. Stages are listed in pipeline order by stages/registry.h.
//
// Artifacts passed between stages, each declared by the stages that write it (spec.outputs,
// `writes`) and read it (spec.inputs, `reads`), so that `pluvia plan` shows who makes and who
// reads each:
//   "image"             the frame, scene-linear (every image stage reads and writes it)
//   "depth"             the frame's "depth" plane, metres
//   "environment"       per-clip lighting (ClipContext::environment)
//   "footage_strokes"   per-clip stroke library cut from rain footage
//   "camera"            the camera every stage draws with (ClipContext::cameraPath)
//   "still"             a still of the clip and the sky in it (ClipContext::still, stillSky)
//   "plate_rain"        whether the plate was shot in rain (ClipContext::plateRain)
//   "first_frame_depth" the depth of the clip's first frame (ClipContext::firstFrameDepth)
//   "found_lamps"       lamps found in the plate (ClipContext::foundLamps)
//   "lights"            the frame's local lights (FrameContext::lights)
// Some are made before or beside the stages: artifactsMadeOutsideStages().
#include <array>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "geometry/camera.h"
#include "geometry/camera_path.h"
#include "image/equirect.h"
#include "image/image.h"
#include "io/clip_reader.h"
#include "optics/local_light.h"
#include "pipeline/plate_lens.h"
#include "preset/preset.h"
#include "rain/streak_types.h"
#include "util/timer.h"

namespace pluvia {

class ArtifactCache;

// Lighting of the shot, in the working colour space: the radiance arriving from every
// direction, as an equirect map (image/equirect.h conventions, world +Y up).
struct Environment {
  EquirectMap radiance;
  std::array<float, 3> averageRgb{0, 0, 0};  // solid-angle mean of radiance
  // The airlight: the sky's radiance at the horizon, where a long path through rain and fog
  // looks (the mean over elevations 0 to 10 deg of a map; the sky model's for the plate's own).
  std::array<float, 3> horizonRgb{0, 0, 0};
  // A looming or dollying camera: environments at key frames (in frame order), to interpolate
  // between per frame; `radiance` is then the middle key's. Empty: one environment for the clip.
  std::vector<std::pair<int64_t, EquirectMap>> keys;
};

// A lamp found in the plate (lights.find, stages/plate_lights.h): a clipped blob of the clip's
// still and the point light it became, placed once per clip.
struct FoundLamp {
  double xPx = 0.0, yPx = 0.0;  // the blob's centroid in the still
  int areaPx = 0;
  double depthMeters = 0.0;                    // z-depth it was placed at
  std::array<double, 3> rgb{1, 1, 1};          // its rim's colour, max channel 1
  double intensity = 0.0;                      // radiant intensity (lights.list units)
  std::array<double, 3> worldMeters{0, 0, 0};  // position in the world (+Y up)
  double radiusMeters = 0.0;
};

// Whether the plate was shot in rain (stages/clip_plate_rain.h).
struct PlateRainFinding {
  bool rained = false;
  // The plate's own streaks' median length and half-maximum width (px at the 640 px measured),
  // and their length over width, the median weighted by their light: the shutter it was filmed
  // with (stages/plate_shutter.h).
  double streakLengthPx = 0.0, streakWidthPx = 0.0, streakElongationByLight = 0.0;
  std::string summary;           // what was measured, for the log
  double measuredSeconds = 0.0;  // for the log too
};

// The shutter the plate was filmed with (stages/plate_shutter.h).
struct PlateShutter {
  double seconds = 0.0;
  std::string source;  // where it comes from, and why, for the log and the plan
  // False where the plate's motion blur gave only an upper bound, or nothing (the 180-degree
  // shutter): the streaks of rain already in the plate may say more.
  bool firm = true;
  // The blur of the plate's still edges (derain::ShutterFromBlur::stillBlurPx), px at the size
  // the motion blur was measured at (the filmed size on a proxy); 0 where it was not measured.
  double stillBlurPx = 0.0;
};

// Per-clip state, filled by per-clip stages in prepare() and read by per-frame stages.
struct ClipContext {
  const ClipInfo* clip = nullptr;
  ClipReader* reader = nullptr;               // frames in the file's encoding
  std::function<Image(int64_t)> readWorking;  // a frame converted to the working space
  // A reader of the same frames of its own, for an analysis that runs on its own thread beside
  // the stages' prepare() (Stage::prepareAhead); empty where none is to (a stage run alone, one
  // thread).
  std::function<std::function<Image(int64_t)>()> openWorkingReader;
  // On a proxy render, a reader of the frames at the size they were filmed at, in the working
  // space (the plate's shutter is measured on them, so a proxy films the rain as the final does);
  // empty otherwise.
  std::function<std::function<Image(int64_t)>()> openFilmedReader;
  // What readWorking gives, as part of a cache key: the plate (clipIdentity), the size it is
  // read at and the conversion into the working space. The per-clip results made from the
  // frames alone (the still, the sky, whether the plate was shot in rain) are cached under it,
  // so a --set change that touches none of these finds them.
  std::string framesKey;
  Camera camera;
  // What the plate's files state of its lens (pipeline/plate_lens.h), set by the render session:
  // `camera` spans its view already; a stage that reads the lens from its own CameraSettings
  // (the depth stage's COLMAP start, the lighting stitch's view, the rain's aperture) takes it
  // through withPlateLens.
  PlateLens plateLens;
  // The width the footage was filmed at over the width rendered (1 / --proxy; RenderRequest::
  // filmedWidthPx): how deep the camera sees rain counts the filmed camera's pixels.
  double filmedScale = 1.0;
  double fps = 24.0;
  ArtifactCache* cache = nullptr;  // null without --cache
  StageTimes* times = nullptr;
  std::optional<Environment> environment;
  std::optional<rain::StrokeAtlas> footageStrokes;
  // The camera every stage draws with: the preset's path (camera.path over `camera`, set by the
  // render session), replaced by the one tracked from the footage (depth stage, COLMAP, which
  // sets cameraTracked).
  CameraPath cameraPath;
  bool cameraTracked = false;
  // A still of the clip and the sky found in it (stages/clip_still.h), made once for the stages
  // that guess from the plate (the default lighting and depth).
  std::optional<Image> still;
  std::optional<std::vector<uint8_t>> stillSky;  // width * height, 1 where sky
  // The depth of the clip's first frame as the depth stage gives it (metres, +inf sky): where
  // the lamps found in the still are placed. Set by the depth stage's prepare() (computed when
  // called: COLMAP's densifies a frame), valid while that stage lives; empty without it.
  std::function<std::vector<float>()> firstFrameDepth;
  // The lamps found in the still (lights.find), set once by the lights stage's prepare(), so
  // that every chunk of a farm render places them alike and `pluvia plan --resolved` lists them.
  std::optional<std::vector<FoundLamp>> foundLamps;
  // Whether the still is a night plate (stages/plate_lights.h), decided on first use by a
  // grading stage that leaves the plate's lamps as they are (stages/lamp_keeping.h).
  std::optional<bool> nightPlate;
  // Measured on first use by a grading stage that leaves itself out on a plate shot in rain, or
  // ahead (plateRainAhead, on a thread of its own) and taken on first use.
  std::optional<PlateRainFinding> plateRain;
  // Found on first use by a stage that films the rain with the plate's shutter.
  std::optional<PlateShutter> plateShutter;
  // The shutter a stage said it films with (stages/plate_shutter.h's resolvePlateShutter): the
  // next stage that films with the same one says so only with -v.
  std::string shutterSaid;
  // The blur of the plate's still edges, px at the size rendered, found on first use by the
  // rain stage (stages/plate_shutter.h's clipPlateStillBlurPx); 0 where none was measured.
  std::optional<double> plateStillBlurPx;
  std::future<PlateRainFinding> plateRainAhead;
};

struct FrameContext {
  int64_t frame = 0;
  double timeSeconds = 0.0;
  Image image;
  // The frame's local lights in its camera space (geometry/camera.h: +X right, +Y up, looking
  // along -Z), as the lights stage resolved them (the preset's, following the camera, and the
  // ones found in the plate), for the rain to light its drops with and the glare to spread; empty
  // without local lights.
  std::vector<optics::LocalLight> lights;
  double lightsExtinctionPerMeter = 0.0;  // the medium between the lights and the drops
  // How much of each pixel a lamp of a night plate holds, found in the frame before the first
  // grading stage changed it (stages/lamp_keeping.h), for every grading stage alike.
  std::optional<std::vector<float>> lampShare;
};

class Stage {
 public:
  virtual ~Stage() = default;
  // Once per clip, before any stage's prepare(): starts an analysis of the frames alone on a
  // thread of its own, so that it runs beside the prepare() of the stages before this one.
  virtual void prepareAhead(ClipContext& clip) {}
  // Once per clip, before any frame (per-clip analysis, GPU set-up).
  virtual void prepare(ClipContext& clip) {}
  // Once per frame, in frame order, on the render thread.
  virtual void process(ClipContext& clip, FrameContext& frame) {}
};

// The artifacts no stage makes alone, and what makes them: the plate's frames ("image"), the
// render session ("camera": the preset's camera.path, which depth replaces when it tracks) and the
// clip's frames analysed on first use by whichever stage asks ("still", "plate_rain").
const std::map<std::string, std::string>& artifactsMadeOutsideStages();

struct StageInfo {
  SectionSpec spec;      // name = preset section; params; static reads/writes for describe
  bool perClip = false;  // per-clip analysis (cacheable) rather than per-frame work
  // Why these parameters make the stage do nothing ("density is 0"), or "" when it does work.
  std::function<std::string(const Preset&)> noOpReason;
  // A remark `pluvia plan` adds when the stage runs ("depth is a guess: ..."), or "".
  std::function<std::string(const Preset&)> note;
  // What it reads and writes with these parameters (subsets of spec.inputs and spec.outputs).
  std::function<std::vector<std::string>(const Preset&)> reads;
  std::function<std::vector<std::string>(const Preset&)> writes;
  // The cache key of the stage's per-clip result for this preset and clip ("" when these
  // parameters cache nothing). A per-frame stage may have one for its per-clip analysis.
  std::function<std::string(const Preset&, const ClipInfo&)> cacheKey;
  // The per-clip work besides its own entry that the stage will find in `cache` under the clip's
  // frames key ("the still ... from the cache"), for `pluvia plan`; "" for none.
  std::function<std::string(const Preset&, const ClipInfo&, const std::string& framesKey,
                            const ArtifactCache&)>
      cachedWork;
  // What every written frame records of these parameters ({"pluvia:seed", "1"}), or none.
  std::function<std::map<std::string, std::string>(const Preset&)> frameMetadata;
  // The stage, holding its section's settings (and those of the sections it reads), read from
  // the preset here, once.
  std::function<std::unique_ptr<Stage>(const Preset&)> create;
};

// StageInfo's callbacks written against the stage's own section: each gets the section's
// settings, read from the preset by the section's settings function, and the preset (for the
// other sections it reads, through their settings functions).
template <class Settings>
struct StageCallbacks {
  bool perClip = false;
  std::function<std::string(const Settings&, const Preset&)> noOpReason = {};
  std::function<std::string(const Settings&, const Preset&)> note = {};
  std::function<std::vector<std::string>(const Settings&, const Preset&)> reads = {};
  std::function<std::vector<std::string>(const Settings&, const Preset&)> writes = {};
  std::function<std::string(const Settings&, const Preset&, const ClipInfo&)> cacheKey = {};
  std::function<std::string(const Settings&, const Preset&, const ClipInfo&,
                            const std::string& framesKey, const ArtifactCache&)>
      cachedWork = {};
  std::function<std::map<std::string, std::string>(const Settings&, const Preset&)> frameMetadata =
      {};
  std::function<std::unique_ptr<Stage>(const Settings&, const Preset&)> create = {};
};

namespace stage_info_detail {

// `typed` as a StageInfo callback: the settings read from the preset first; empty stays empty.
template <class Settings, class Result, class... Rest>
std::function<Result(const Preset&, Rest...)> withSettings(
    Settings (*read)(const Preset&),
    std::function<Result(const Settings&, const Preset&, Rest...)> typed) {
  if (!typed) return {};
  return [read, typed = std::move(typed)](const Preset& preset, Rest... rest) {
    return typed(read(preset), preset, rest...);
  };
}

}  // namespace stage_info_detail

// The StageInfo of the stage that owns the section `spec`, whose settings `read` gives:
//   makeStageInfo(blurTable().section(), blurSettings, {.noOpReason = ..., .create = ...})
template <class Settings>
StageInfo makeStageInfo(SectionSpec spec, Settings (*read)(const Preset&),
                        StageCallbacks<Settings> callbacks) {
  using stage_info_detail::withSettings;
  StageInfo info;
  info.spec = std::move(spec);
  info.perClip = callbacks.perClip;
  info.noOpReason = withSettings(read, std::move(callbacks.noOpReason));
  info.note = withSettings(read, std::move(callbacks.note));
  info.reads = withSettings(read, std::move(callbacks.reads));
  info.writes = withSettings(read, std::move(callbacks.writes));
  info.cacheKey = withSettings(read, std::move(callbacks.cacheKey));
  info.cachedWork = withSettings(read, std::move(callbacks.cachedWork));
  info.frameMetadata = withSettings(read, std::move(callbacks.frameMetadata));
  info.create = withSettings(read, std::move(callbacks.create));
  return info;
}

// Hash of a clip's identity for cache keys and resumed frames: file paths, sizes and
// modification times, and the first and last MiB of its first, middle and last files (a plate
// replaced in place keeping its size and time is another plate).
std::string clipIdentity(const ClipInfo& clip);

}  // namespace pluvia
