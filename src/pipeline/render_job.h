#pragma once
// A render job: a clip in, rained frames out. Reading (decode + colour in) runs on its own
// thread, the stages on the render thread that owns the GL context, and encoding on a pool of
// writer threads (one for movies, which need frames in order), so I/O overlaps the work.
// Frames are independent of thread count and chunking: every per-frame result depends only on
// the preset, the seed and the frame number.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "image/color.h"
#include "io/clip_writer.h"
#include "io/output_target.h"
#include "pipeline/cache.h"
#include "pipeline/camera_settings.h"
#include "pipeline/color_settings.h"
#include "pipeline/planner.h"
#include "util/timer.h"

namespace pluvia {

struct RenderRequest {
  std::string input;
  OutputTarget output;  // told once what it is (OutputTarget::classify)
  // --start-frame: the number of a movie's first frame (movies count from 0 otherwise).
  std::optional<int64_t> movieFirstFrame;
  std::optional<int64_t> firstFrame;  // inclusive, clip frame numbers
  std::optional<int64_t> lastFrame;
  // A stepped or comma list ("1001-1100x2", "1,5,9"), ascending; every one must be in the clip.
  // Empty: the range above.
  std::vector<int64_t> frameList;
  int threads = 2;       // writer threads for sequences
  std::string cacheDir;  // per-clip analysis cache; empty: none
  // Fail before any work when per-clip analysis is missing from cacheDir, instead of computing
  // it: farm chunks, after `pluvia prepare` filled the cache.
  bool requireCache = false;
  bool skipExisting = false;
  std::vector<std::string> aovs;  // "rain", "matte", "depth"
  std::string commandLine;        // recorded in the log
  bool progress = true;
  // Proxy render, in (0, 1]: every frame is resized by this factor right after reading, so the
  // camera, the analysis, the rain and the output all work at the reduced size. 1: full size.
  double proxyScale = 1.0;
  // The width the footage was filmed at, when the input stands for footage filmed at another size
  // (`pluvia report realism` renders on plates scaled to 640 px); 0: the input's own, before
  // --proxy. rain.far_m 0 counts its pixels (rain/rain_depth.h), so a proxy or a measuring copy
  // draws the rain the full-size camera sees.
  int filmedWidthPx = 0;
  // How the output is written: movie codec, EXR sample type and compression (the rest of
  // WriterOptions is filled in from the clip and the preset).
  WriterOptions format;
};

struct RenderSummary {
  int framesWritten = 0;
  int framesSkipped = 0;  // --skip-existing: whole frames of this preset, kept
  int framesRedone = 0;   // --skip-existing: broken or other-preset frames, rendered again
  Plan plan;
};

// A render set up for one clip: the input opened (at the proxy size), the frames selected, the
// plan made, the colour conversions ready and, after prepareStages(), the stages built and
// prepared. renderJob() drives it over its threads; `pluvia preview` renders a few frames with
// it, so both give the same frames.
class RenderSession {
 public:
  // Opens the input, selects the frames, refuses an output that names an input file, plans, and
  // logs the command, the resolved preset and the plan. `stages` lists every stage in pipeline
  // order (stages/registry.h: allStages()); the arguments must outlive the session.
  RenderSession(const RenderRequest& request, const Preset& preset,
                const std::vector<StageInfo>& stages, StageTimes& times);
  RenderSession(const RenderSession&) = delete;
  RenderSession& operator=(const RenderSession&) = delete;

  const ClipInfo& clip() const { return reader_->info(); }        // at the proxy size
  const std::vector<int64_t>& frames() const { return frames_; }  // request's range, in order
  const Plan& plan() const { return plan_; }
  // The per-clip analysis cache (a proxy's own folder under --cache), or null without --cache.
  const ArtifactCache* cache() const { return cache_ ? &*cache_ : nullptr; }
  // What the output files record: fps, AOVs and metadata (`pluvia:proxy` on a proxy render).
  const WriterOptions& writerOptions() const { return writerOptions_; }

  // Builds the stages the plan keeps and prepares them (per-clip analysis, GPU set-up). Once,
  // before processFrame(). A per-clip cache entry missing from the cache is computed by one
  // process, the others waiting for it (pipeline/clip_analysis.h).
  void prepareStages();
  // Builds and prepares only the named stages the plan keeps, in pipeline order (`pluvia plan
  // --resolved`: the depth and the lamps found in the plate, without the rest's analysis).
  void prepareStagesNamed(const std::vector<std::string>& names);
  // The per-clip state the prepared stages filled in.
  const ClipContext& clipContext() const { return context_; }
  // The same for a per-clip finding made outside the stages (`pluvia plan`: the plate's shutter).
  ClipContext& clipContext() { return context_; }
  // The frame decoded, its NaN/Inf replaced (with a warning) and converted to the working space.
  FrameContext readFrame(int64_t frame);
  // Runs the per-frame stages (frames in increasing order); a frame no stage gave depth gets
  // +infinity (sky), and the request's AOV planes exist afterwards (zeros where nothing drew).
  void processFrame(FrameContext& frame);
  // Converts RGB from the working space to the output's encoding (as written to request.output).
  void toOutput(Image& image) const;

 private:
  // A frame of `reader` in the working space.
  Image workingFrame(ClipReader& reader, int64_t frame) const;
  const RenderRequest& request_;
  const Preset& preset_;
  const std::vector<StageInfo>& stageInfos_;
  StageTimes& times_;
  std::unique_ptr<ClipReader> reader_;
  std::vector<int64_t> frames_;
  std::optional<ArtifactCache> cache_;
  // workingFramesKey of the clip, with a cache only (it reads samples of the plate's files).
  std::string framesKey_;
  Plan plan_;
  ColorSettings color_;
  CameraSettings camera_;
  ColorConverter toWorking_;
  ColorConverter toOutput_;
  WriterOptions writerOptions_;
  // The working value of each of the movie's codes (ColorConverter::codeValues), when its
  // frames are converted as they are unpacked; empty when toWorking_ converts whole frames.
  std::optional<CodeValues> workingCodes_;
  // The rain layer's planes of the last frame, handed to the next as scratch (processFrame).
  std::map<std::string, std::vector<float>> rainScratch_;
  ClipContext context_;
  std::vector<std::pair<const StageInfo*, std::unique_ptr<Stage>>> stages_;  // pipeline order
  std::vector<std::pair<std::string, Stage*>> frameStages_;  // per-frame stages that run
};

// Opens the input and plans the job for it, without rendering.
Plan planJob(const std::string& input, std::optional<int64_t> movieFirstFrame, const Preset& preset,
             const std::string& cacheDir, const std::vector<StageInfo>& stages,
             ClipInfo* clipOut = nullptr);

// Renders: refuses one image file for many frames, locks the output, keeps the frames
// --skip-existing finds done (pipeline/skip_existing.h), prepares the stages and runs the frame
// loop (pipeline/frame_threads.h). Throws pluvia::Error (naming stage, frame and file) on any
// failure; frames already written stay valid, no partial frame is left behind, and no input file is
// ever written. `stages` lists every stage in pipeline order (stages/registry.h: allStages()).
// What a movie's colour tags say its RGB is in, for color.input "auto": the config's sRGB space
// for the sRGB curve, its Rec.709 / Rec.2020 video space (image/color.h) for the Rec.709 OETF
// (which BT.601 and SDR BT.2020 share) on those primaries. Nothing for a sequence, an untagged
// movie, or tags pluvia does not read (HLG, PQ), which are read as sRGB; `note` says which.
std::optional<std::string> movieTaggedSpace(const ClipInfo& clip, const std::string& configPath,
                                            std::string* note = nullptr);
// The same where color.input is "auto", else nothing: a space the user gave for the plate
// overrides its tags, and its outputs are not taken into the tagged space either.
std::optional<std::string> taggedInputSpace(const ColorSettings& color, const ClipInfo& clip);
// What ClipContext::readWorking gives for this preset and clip, as a cache key (the session's
// ClipContext::framesKey): the plate, the size read, the conversion into the working space.
std::string workingFramesKey(const Preset& preset, const ClipInfo& clip);
// The colour space of the frames written to `output` (color.output; "auto": the working space
// for EXR/HDR, the space a tagged movie came in (`taggedInputSpace`), else the config's sRGB
// space), and the tags a file says it with: a render and a farm's assembly of its frames into a
// movie tag alike.
std::string resolveOutputSpace(const ColorSettings& color, const std::string& output,
                               const std::optional<std::string>& taggedInputSpace = std::nullopt);
ColorTags outputColorTags(const ColorSettings& color, const std::string& output,
                          const std::optional<std::string>& taggedInputSpace = std::nullopt);

RenderSummary renderJob(const RenderRequest& request, const Preset& preset,
                        const std::vector<StageInfo>& stages, StageTimes& times);

}  // namespace pluvia
