#pragma once
// The Stage interface and the data a stage declares about itself (FFmpeg AVFilter style):
// its section of the preset (parameter table, reads, writes), when it is a no-op, and how to
// build it. Stages are listed in pipeline order by stages/registry.h.
//
// Artifacts passed between stages:
//   "image"           the frame, scene-linear (every image stage reads and writes it)
//   "depth"           the frame's "depth" plane, metres
//   "environment"     per-clip lighting (SH coefficients and average colour)
//   "footage_strokes" per-clip stroke library cut from rain footage
#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "geometry/camera.h"
#include "geometry/camera_path.h"
#include "image/equirect.h"
#include "image/image.h"
#include "io/clip_reader.h"
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

// Per-clip state, filled by per-clip stages in prepare() and read by per-frame stages.
struct ClipContext {
  const ClipInfo* clip = nullptr;
  ClipReader* reader = nullptr;               // frames in the file's encoding
  std::function<Image(int64_t)> readWorking;  // a frame converted to the working space
  Camera camera;
  double fps = 24.0;
  ArtifactCache* cache = nullptr;  // null without --cache
  StageTimes* times = nullptr;
  std::optional<Environment> environment;
  std::optional<rain::StrokeAtlas> footageStrokes;
  // The camera tracked from the footage (depth stage, COLMAP): it replaces the preset's camera
  // for the rain.
  std::optional<CameraPath> trackedPath;
  // A still of the clip and the sky found in it (stages/clip_still.h), made once for the stages
  // that guess from the plate (the default lighting and depth).
  std::optional<Image> still;
  std::optional<std::vector<uint8_t>> stillSky;  // width * height, 1 where sky
};

struct FrameContext {
  int64_t frame = 0;
  double timeSeconds = 0.0;
  Image image;
};

class Stage {
 public:
  virtual ~Stage() = default;
  // Once per clip, before any frame (per-clip analysis, GPU set-up).
  virtual void prepare(ClipContext& clip) {}
  // Once per frame, in frame order, on the render thread.
  virtual void process(ClipContext& clip, FrameContext& frame) {}
};

struct StageInfo {
  SectionSpec spec;      // name = preset section; params; static reads/writes for describe
  bool perClip = false;  // per-clip analysis (cacheable) rather than per-frame work
  // Why these parameters make the stage do nothing ("density is 0"), or "" when it does work.
  std::function<std::string(const Preset&)> noOpReason;
  // A remark `pluvia plan` adds when the stage runs ("depth is a guess: ..."), or "".
  std::function<std::string(const Preset&)> note;
  // What it reads with these parameters (a subset of spec.inputs).
  std::function<std::vector<std::string>(const Preset&)> reads;
  // The cache key of the stage's per-clip result for this preset and clip ("" when these
  // parameters cache nothing). A per-frame stage may have one for its per-clip analysis.
  std::function<std::string(const Preset&, const ClipInfo&)> cacheKey;
  // What every written frame records of these parameters ({"pluvia:seed", "1"}), or none.
  std::function<std::map<std::string, std::string>(const Preset&)> frameMetadata;
  // The stage, holding its section's settings (and those of the sections it reads), read from
  // the preset here, once.
  std::function<std::unique_ptr<Stage>(const Preset&)> create;
};

// Hash of a clip's identity for cache keys: file paths, sizes and modification times.
std::string clipIdentity(const ClipInfo& clip);

}  // namespace pluvia
