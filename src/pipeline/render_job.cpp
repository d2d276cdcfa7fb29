#include "pipeline/render_job.h"

#include <algorithm>
#include <filesystem>
#include <limits>
#include <memory>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "image/color.h"
#include "image/ops.h"
#include "io/clip_writer.h"
#include "io/color_tags.h"
#include "io/output_lock.h"
#include "io/sequence_pattern.h"
#include "io/timecode.h"
#include "pipeline/cache.h"
#include "pipeline/cached_clip_open.h"
#include "pipeline/clip_analysis.h"
#include "pipeline/frame_metadata.h"
#include "pipeline/frame_threads.h"
#include "pipeline/numbered_clip_reader.h"
#include "pipeline/plate_lens.h"
#include "pipeline/proxy_clip_reader.h"
#include "pipeline/skip_existing.h"
#include "util/fs.h"
#include "util/hash.h"
#include "util/input_guard.h"
#include "util/interrupt.h"
#include "util/log.h"

namespace pluvia {
namespace {

// A movie's frames are decoded from integer codes (io/movie_reader.cpp: Y'CbCr through a finite
// matrix, or RGB): they hold no NaN or infinity, and a 1080p frame's scan for them costs a few
// milliseconds.
bool mayHoldNonFinite(const ClipInfo& clip) {
  return !clip.isMovie;
}

// "auto": float files are scene-linear (the config's scene_linear role), a movie what its colour
// tags say (movieTaggedSpace), other integer files display-encoded sRGB (the config's space for
// it: image/color.h).
std::string resolveInputSpace(const ColorSettings& color, const ClipInfo& clip) {
  if (color.inputSpace != "auto") return color.inputSpace;
  if (clip.isFloat) return "scene_linear";
  return taggedInputSpace(color, clip).value_or(srgbEncodedSpace(color.configPath));
}

std::vector<int64_t> selectFrames(const RenderRequest& request, const ClipInfo& clip) {
  for (int64_t f : request.frameList) {
    if (!std::binary_search(clip.frames.begin(), clip.frames.end(), f)) {
      throw Error(fmt::format("frame {} of --frames is not in {} (it has frames {}-{})", f,
                              clip.path, clip.frames.front(), clip.frames.back()),
                  {"read", f, clip.path});
    }
  }
  if (!request.frameList.empty()) return request.frameList;
  std::vector<int64_t> frames;
  for (int64_t f : clip.frames) {
    if (request.firstFrame && f < *request.firstFrame) continue;
    if (request.lastFrame && f > *request.lastFrame) continue;
    frames.push_back(f);
  }
  if (frames.empty()) {
    throw UsageError(fmt::format("--frames {}-{} selects no frame of {} (it has frames {}-{})",
                                 request.firstFrame.value_or(clip.frames.front()),
                                 request.lastFrame.value_or(clip.frames.back()), clip.path,
                                 clip.frames.front(), clip.frames.back()),
                     {"read", {}, clip.path});
  }
  // A hole in a sequence is an error before any work: a farm must not render around it silently.
  for (size_t i = 1; i < frames.size(); ++i) {
    if (frames[i] != frames[i - 1] + 1) {
      std::string missing = fmt::format("{}", frames[i - 1] + 1);
      if (auto pattern = SequencePattern::parse(clip.path))
        missing += " (" + pattern->pathFor(frames[i - 1] + 1) + ")";
      throw Error(fmt::format("frame {} is missing from the sequence {}", missing, clip.path),
                  {"read", frames[i - 1] + 1, clip.path});
    }
  }
  if (request.firstFrame && frames.front() != *request.firstFrame) {
    throw Error(fmt::format("frame {} is not in {} (it starts at {})", *request.firstFrame,
                            clip.path, frames.front()),
                {"read", *request.firstFrame, clip.path});
  }
  if (request.lastFrame && frames.back() != *request.lastFrame) {
    throw Error(fmt::format("frame {} is not in {} (it ends at {})", *request.lastFrame, clip.path,
                            frames.back()),
                {"read", *request.lastFrame, clip.path});
  }
  return frames;
}

// Registers with fs::protectInputs every file a preset's value names (lighting.hdr, depth.file
// and its frames, depth.colmap_model's files, derain.input, rain.strokes, color.config): each is
// read by a stage only once the render runs, and the outputs are checked before that. A string
// that names no file protects nothing.
void protectFilesNamedIn(const nlohmann::json& value) {
  if (value.is_object() || value.is_array()) {
    for (const nlohmann::json& item : value) protectFilesNamedIn(item);
    return;
  }
  if (!value.is_string()) return;
  const std::string text = value.get<std::string>();
  std::error_code ec;
  if (text.empty() || text.size() > 4096) return;
  if (std::filesystem::is_directory(text, ec)) {  // a COLMAP model's folder
    std::vector<std::string> files;
    for (const auto& entry : std::filesystem::directory_iterator(text, ec))
      if (entry.is_regular_file(ec)) files.push_back(entry.path().string());
    fs::protectInputs(files);
  } else if (std::filesystem::exists(text, ec)) {
    fs::protectInputs({text});
  } else if (std::optional<SequencePattern> pattern = SequencePattern::parse(text)) {
    std::vector<std::string> files;
    for (const int64_t frame : pattern->existingFrames()) files.push_back(pattern->pathFor(frame));
    fs::protectInputs(files);
  }
}

// Refuses any file the render would write (the beauty, an AOV's own file) that is one of the
// input files: the original plate is never touched, nor a file the preset names. The inputs are
// also registered with fs::protectInputs, which every later write (reports, the log) checks.
void refuseOverwritingInput(const ClipInfo& clip, const RenderRequest& request,
                            const Preset& preset, const std::vector<int64_t>& frames) {
  std::set<std::string> inputs(clip.files.begin(), clip.files.end());
  inputs.insert(clip.path);
  fs::protectInputs({inputs.begin(), inputs.end()});
  protectFilesNamedIn(preset.json());
  const bool oneFile = !request.output.isSequence();
  for (const int64_t frame : oneFile ? std::vector<int64_t>{frames.front()} : frames) {
    for (const std::string& out : framePaths(request.output, request.aovs, frame)) {
      fs::claimOutput(out, "-o");
      fs::refuseSpecialTarget(out);
      const std::string in = fs::protectedInputAt(out);
      if (!in.empty())
        throw UsageError(
            fmt::format("output {} is the input file {}: refusing to overwrite it", out, in),
            {"write", {}, in});
    }
  }
}

// A name over the file system's limit would fail only at the first write, after the per-clip
// analysis: said before any work.
void refuseNamesTooLongToWrite(const RenderRequest& request, int64_t frame) {
  for (const std::string& out : framePaths(request.output, request.aovs, frame)) {
    const std::string name = std::filesystem::path(out).filename().string();
    if (name.size() > fs::kNameMaxBytes)
      throw UsageError(fmt::format("the output file name {} is {} bytes, over the file system's "
                                   "{}: shorten it",
                                   name, name.size(), fs::kNameMaxBytes),
                       {"write", {}, out});
  }
}

// One image file holds one frame: more frames into it would each overwrite the last.
void refuseSingleFileForManyFrames(const OutputTarget& output, const std::vector<int64_t>& frames) {
  if (frames.size() < 2 || output.kind != OutputTarget::Kind::SingleImage) return;
  const std::filesystem::path path(output.path);
  const std::string pattern =
      (path.parent_path() / path.stem()).string() + ".####" + path.extension().string();
  throw UsageError(
      fmt::format("output {} is one image file, but {} frames ({}-{}) are rendered: give a "
                  "sequence such as {}, a movie, or one frame with --frames",
                  output.path, frames.size(), frames.front(), frames.back(), pattern),
      {"write", {}, output.path});
}

// The AOVs of what a stage changed (stages/depth_grading.h, GradingAov): wet_ground, darken,
// blur, fog, ripples and splash.
bool isGradingAov(const std::string& aov) {
  return aov == "wet_ground" || aov == "darken" || aov == "blur" || aov == "fog" ||
         aov == "ripples" || aov == "splash";
}

void ensureAovPlanes(Image& image, const std::vector<std::string>& aovs) {
  for (const auto& aov : aovs) {
    if (aov == "rain" || aov == "lights" || aov == "glare" || isGradingAov(aov)) {
      for (const char* c : {"R", "G", "B", "A"}) image.plane(aov + "." + c);
    } else {
      image.plane(aov);
    }
  }
}

// The input, read at the proxy size when the request asks for one.
std::unique_ptr<ClipReader> openInput(const RenderRequest& request) {
  std::unique_ptr<ClipReader> reader =
      openNumberedClipWithCache(request.input, request.movieFirstFrame, request.cacheDir);
  if (request.proxyScale == 1.0) return reader;
  return std::make_unique<ProxyClipReader>(std::move(reader), request.proxyScale);
}

// The frames to render; an output that names an input file is refused before any work.
std::vector<int64_t> framesToRender(const RenderRequest& request, const ClipInfo& clip,
                                    const Preset& preset) {
  std::vector<int64_t> frames = selectFrames(request, clip);
  refuseOverwritingInput(clip, request, preset, frames);
  refuseNamesTooLongToWrite(request, frames.back());
  if (request.output.isMovie()) {
    WriterOptions options = request.format;
    options.aovs = request.aovs;
    checkMovieAovs(request.output.path, options);
  }
  return frames;
}

// A proxy render's per-clip analysis is measured on the smaller frames (COLMAP's focal length
// is in its pixels), so it is cached apart from the full-size render's, in a folder named by
// the frame size.
std::optional<ArtifactCache> openCache(const RenderRequest& request, const ClipInfo& clip) {
  if (request.cacheDir.empty()) return std::nullopt;
  if (request.proxyScale == 1.0) return ArtifactCache(request.cacheDir);
  return ArtifactCache(std::filesystem::path(request.cacheDir) /
                       fmt::format("proxy-{}x{}", clip.width, clip.height));
}

// What the input says about itself goes on to the output (io/clip_reader.h): camera and lens
// fields as they are, the timecode counted on to the first frame rendered, and an EXR's data
// window (scaled with a proxy).
void carryInputMetadata(WriterOptions& options, const ClipInfo& clip,
                        const std::vector<int64_t>& frames, double proxyScale) {
  for (const auto& [key, value] : clip.metadata)
    if (key != "smpte:TimeCode") options.metadata[key] = value;
  auto timecode = clip.metadata.find("smpte:TimeCode");
  if (timecode != clip.metadata.end()) {
    if (auto start = Timecode::parse(timecode->second, options.fps)) {
      options.timecode = start->plus(frames.front() - clip.frames.front());
      options.firstFrame = frames.front();
    } else {
      log::warning(
          fmt::format("the timecode '{}' of {} does not read as HH:MM:SS:FF at {:g} fps: "
                      "not carried to the output",
                      timecode->second, clip.path, options.fps));
    }
  }
  if (clip.dataWindow && proxyScale == 1.0) options.dataWindow = clip.dataWindow;
  options.displayWindow = clip.displayWindow;  // a proxy's, scaled with its frames
}

// The camera of the plate's picture (its field of view spans the display window), its frame
// grown to the overscan around it: the principal point moves with the picture's place.
Camera cameraOfFrame(const CameraSettings& settings, const ClipInfo& clip) {
  if (!clip.displayWindow) return settings.base(clip.width, clip.height);
  const PixelWindow& picture = *clip.displayWindow;
  Camera camera = settings.base(picture.width, picture.height);
  camera.width = clip.width;
  camera.height = clip.height;
  camera.cx += picture.x;
  camera.cy += picture.y;
  return camera;
}

// The colour config as a hash of the file it is (absolute, links resolved: not as the preset
// or $OCIO spells it) and its text; the built-in one by its description.
std::string configIdentity(const ColorSettings& color) {
  Hasher config;
  const std::string configFile = chosenConfigPath(color.configPath);
  if (configFile.empty() || configFile.rfind("ocio://", 0) == 0) {
    config.add(describeConfig(color.configPath));
    return config.hex();
  }
  config.add(fs::canonicalSpelling(configFile).string());
  config.add(fs::readInputText(configFile, "the OpenColorIO config"));
  return config.hex();
}

// What a frame's pixels and file depend on besides the preset, recorded in its header so that
// --skip-existing keeps only a frame this render would write alike (io/written_frame.h): the
// plate (pipeline/stage.h's clipIdentity), the output size, the colour config and spaces, the
// AOVs and the file format's options. pluvia:presetHash, pluvia:version and pluvia:proxy are
// recorded already. No value holds ';' (TIFF and JPEG keep them as "key=value; ...").
void addResumeIdentity(WriterOptions& options, const RenderRequest& request,
                       const ColorSettings& color, const ClipInfo& clip) {
  options.metadata["pluvia:plate"] = clipIdentity(clip);
  options.metadata["pluvia:size"] = fmt::format("{}x{}", clip.width, clip.height);
  options.metadata["pluvia:colour"] =
      fmt::format("{} -> {} -> {}, config {}", resolveInputSpace(color, clip), color.workingSpace,
                  resolveOutputSpace(color, request.output.path, taggedInputSpace(color, clip)),
                  configIdentity(color));
  options.metadata["pluvia:aovs"] =
      request.aovs.empty() ? "none" : fmt::format("{}", fmt::join(request.aovs, ","));
  const std::string extension = lowerExtension(request.output.path);
  options.metadata["pluvia:format"] =
      extension == "exr" ? fmt::format("exr {} {}", options.exrSampleType, options.exrCompression)
      : extension == "tif" || extension == "tiff"
          ? fmt::format("{} {}", extension, options.tiffSampleType)
          : extension;
}

WriterOptions writerOptionsFor(const RenderRequest& request, const Preset& preset,
                               const std::vector<StageInfo>& stages, const CameraSettings& camera,
                               const ColorSettings& color, const ClipInfo& clip,
                               const std::vector<int64_t>& frames) {
  WriterOptions options = request.format;
  options.fps = camera.framesPerSecondOf(clip.fps);
  options.aovs = request.aovs;
  options.metadata = frameMetadata(preset, stages);
  carryInputMetadata(options, clip, frames, request.proxyScale);
  options.color = outputColorTags(color, request.output.path, taggedInputSpace(color, clip));
  // Grey and alpha, or RGBA: the plate's alpha goes out; an RGB plate's frames stay RGB.
  options.alpha = clip.channels == 2 || clip.channels >= 4;
  // A proxy frame must never pass for a final one: it says so in its header.
  if (request.proxyScale != 1.0)
    options.metadata["pluvia:proxy"] =
        fmt::format("{:g} ({}x{})", request.proxyScale, clip.width, clip.height);
  // A movie is kept or redone whole by its frame count (io/written_frame.h); its comment stays
  // what `farm assemble` writes too, so both movies are alike.
  if (!request.output.isMovie()) addResumeIdentity(options, request, color, clip);
  return options;
}

}  // namespace

std::string workingFramesKey(const Preset& preset, const ClipInfo& clip) {
  const ColorSettings color = colorSettings(preset);
  return Hasher()
      .add(clipIdentity(clip))
      .add(uint64_t(clip.width))
      .add(uint64_t(clip.height))
      .add(resolveInputSpace(color, clip))
      .add(color.workingSpace)
      .add(configIdentity(color))
      .hex();
}

std::optional<std::string> movieTaggedSpace(const ClipInfo& clip, const std::string& configPath,
                                            std::string* note) {
  if (!clip.isMovie || clip.isFloat) return std::nullopt;
  auto tag = [&](const char* field) {
    const auto found = clip.metadata.find(std::string("ffmpeg:") + field);
    return found == clip.metadata.end() ? std::string() : found->second;
  };
  auto say = [&](std::string text) {
    if (note) *note = std::move(text);
  };
  const std::string transfer = tag("color_transfer"), primaries = tag("color_primaries");
  if (transfer.empty()) {
    say("the movie has no colour transfer tag: read as sRGB (--in-colorspace says otherwise)");
    return std::nullopt;
  }
  if (transfer == "iec61966-2-1") {
    say("the movie is tagged sRGB (iec61966-2-1): read as sRGB");
    return srgbEncodedSpace(configPath);
  }
  // BT.601 and SDR BT.2020 use the Rec.709 camera OETF too.
  static const std::set<std::string> kRec709Oetf{"bt709", "smpte170m", "bt2020-10", "bt2020-12"};
  if (kRec709Oetf.count(transfer)) {
    if (std::optional<std::string> space = videoEncodedSpace(primaries, configPath)) {
      say(fmt::format("the movie is tagged {} on {} primaries: read as {}", transfer,
                      primaries.empty() ? "unstated" : primaries, *space));
      return space;
    }
    say(
        fmt::format("the movie is tagged {}, but the config has no space for it: read as sRGB "
                    "(--in-colorspace says otherwise)",
                    transfer));
    return std::nullopt;
  }
  say(
      fmt::format("the movie's colour transfer {} is not one pluvia reads (sRGB, BT.709, "
                  "BT.601, BT.2020 SDR): read as sRGB (--in-colorspace says otherwise)",
                  transfer));
  return std::nullopt;
}

std::optional<std::string> taggedInputSpace(const ColorSettings& color, const ClipInfo& clip) {
  if (color.inputSpace != "auto") return std::nullopt;
  return movieTaggedSpace(clip, color.configPath);
}

// "auto": EXR and HDR get the working space; other formats the space a tagged movie came in
// (so that a BT.709 plate goes out BT.709), else display-encoded sRGB.
std::string resolveOutputSpace(const ColorSettings& color, const std::string& output,
                               const std::optional<std::string>& taggedInputSpace) {
  if (color.outputSpace != "auto") return color.outputSpace;
  if (outputIsLinear(output)) return color.workingSpace;
  return taggedInputSpace.value_or(srgbEncodedSpace(color.configPath));
}

ColorTags outputColorTags(const ColorSettings& color, const std::string& output,
                          const std::optional<std::string>& taggedInputSpace) {
  return colorTagsFor(
      colorSpaceNamesOf(resolveOutputSpace(color, output, taggedInputSpace), color.configPath));
}

RenderSession::RenderSession(const RenderRequest& request, const Preset& preset,
                             const std::vector<StageInfo>& stages, StageTimes& times)
    : request_(request),
      preset_(preset),
      stageInfos_(stages),
      times_(times),
      reader_(openInput(request)),
      frames_(framesToRender(request, clip(), preset)),
      cache_(openCache(request, clip())),
      framesKey_(cache_ ? workingFramesKey(preset, clip()) : ""),
      plan_(makePlan(preset, clip(), cache_ ? &*cache_ : nullptr, framesKey_, stages)),
      color_(colorSettings(preset)),
      camera_(cameraSettings(preset)),
      toWorking_(resolveInputSpace(color_, clip()), color_.workingSpace, color_.configPath),
      toOutput_(color_.workingSpace,
                resolveOutputSpace(color_, request.output.path, taggedInputSpace(color_, clip())),
                color_.configPath),
      writerOptions_(writerOptionsFor(request, preset, stages, camera_, color_, clip(), frames_)) {
  log::info("command: " + request.commandLine);
  log::info(
      fmt::format("colour: {} -> {} (working) -> {}, config: {}", resolveInputSpace(color_, clip()),
                  color_.workingSpace,
                  resolveOutputSpace(color_, request.output.path, taggedInputSpace(color_, clip())),
                  describeConfig(color_.configPath)));
  if (std::string note; color_.inputSpace == "auto") {
    movieTaggedSpace(clip(), color_.configPath, &note);
    if (!note.empty()) log::info("colour: " + note);
  }
  // The bounded copy the frames record: a preset with a 50 MB description stays out of the log.
  // With -v only: every frame's header holds it, and `pluvia plan --resolved` prints it.
  log::debug("preset (resolved): " + writerOptions_.metadata.at("pluvia:preset"));
  // The stages in one line; each stage's note and the artifacts with -v (or `pluvia plan`).
  log::info("plan: " + plan_.summary());
  log::debug("plan:\n" + plan_.text());
  log::debug(fmt::format(
      "input: {}x{}, {} bits a sample, {:g} fps; output tagged '{}'{}{}", clip().width,
      clip().height, clip().bitsPerSample, writerOptions_.fps, writerOptions_.color.name,
      writerOptions_.timecode ? ", timecode " + writerOptions_.timecode->text() : std::string(),
      writerOptions_.dataWindow ? ", the input's data window" : "",
      clip().displayWindow ? fmt::format(", overscan around a {}x{} picture",
                                         clip().displayWindow->width, clip().displayWindow->height)
                           : std::string()));
  if (request.proxyScale != 1.0)
    log::info(fmt::format("proxy render (not a final): {}x{}, {:g} of the plate's size",
                          clip().width, clip().height, request.proxyScale));

  context_.clip = &clip();
  context_.reader = reader_.get();
  context_.cache = cache_ ? &*cache_ : nullptr;
  context_.times = &times;
  context_.fps = writerOptions_.fps;
  // The plate's own lens where its files state it: the view the clip's camera spans (the stages
  // take the rest from ClipContext::plateLens).
  context_.plateLens = statedLens(clip());
  camera_ = withPlateLens(camera_, context_.plateLens);
  // From the clip's size as read: a proxy's smaller frames get a proportionally shorter focal
  // length in pixels, so the rain and the depth land where they would on the full frame.
  context_.camera = cameraOfFrame(camera_, clip());
  context_.cameraPath = camera_.path(context_.camera);
  context_.filmedScale = request.filmedWidthPx > 0 ? double(request.filmedWidthPx) / clip().width
                                                   : 1.0 / request.proxyScale;
  context_.framesKey = framesKey_;
  // A movie's 8- or 16-bit codes looked up in the working space as they are unpacked: the
  // values toWorking_.apply() gives, without a pass over the frame.
  if (const int bits = reader_->codeBits(); bits && !mayHoldNonFinite(clip()))
    workingCodes_ = toWorking_.codeValues(bits);
  context_.readWorking = [this](int64_t frame) { return workingFrame(*reader_, frame); };
  // Declared after reader_ and toWorking_, context_ (and an analysis it waits for) ends first.
  context_.openWorkingReader = [this] {
    std::shared_ptr<ClipReader> reader = openInput(request_);
    return std::function<Image(int64_t)>(
        [this, reader](int64_t frame) { return workingFrame(*reader, frame); });
  };
  if (request.proxyScale != 1.0) {
    context_.openFilmedReader = [this] {
      std::shared_ptr<ClipReader> reader =
          openNumberedClipWithCache(request_.input, request_.movieFirstFrame, request_.cacheDir);
      return std::function<Image(int64_t)>(
          [this, reader](int64_t frame) { return workingFrame(*reader, frame); });
    };
  }
}

Image RenderSession::workingFrame(ClipReader& reader, int64_t frame) const {
  if (workingCodes_) return reader.readCodesThrough(frame, *workingCodes_);
  Image image = reader.read(frame);
  if (mayHoldNonFinite(clip())) ops::replaceNonFinite(image);
  toWorking_.apply(image);
  return image;
}

void RenderSession::prepareStages() {
  if (request_.requireCache && cache_)
    requireCachedAnalysis(clipAnalysisEntries(plan_, preset_, clip(), stageInfos_, *cache_),
                          request_.input, request_.cacheDir);
  for (const auto& info : stageInfos_) {
    if (!plan_.available(info.spec.name)) continue;
    stages_.emplace_back(&info, info.create(preset_));
  }
  for (auto& [info, stage] : stages_) stage->prepareAhead(context_);
  for (auto& [info, stage] : stages_) {
    const std::string& name = info->spec.name;
    ScopedTimer timer(&times_, name + " (prepare)");
    throwIfInterrupted();  // a stop asked for during the analysis before: no further one
    try {
      // Held while the stage computes its missing cache entry, so that it is computed once.
      const auto entryLock = lockMissingEntry(cache_ ? &*cache_ : nullptr, *info, preset_, clip());
      stage->prepare(context_);
    } catch (const Error& e) {
      if (!e.context().stage.empty()) throw;
      throw Error(e.what(), {name, {}, e.context().file});
    }
  }
  throwIfInterrupted();
  // Only per-frame stages that run take part in the frame loop; per-clip ones are done.
  for (auto& [info, stage] : stages_) {
    if (!info->perClip && plan_.runs(info->spec.name))
      frameStages_.emplace_back(info->spec.name, stage.get());
  }
}

void RenderSession::prepareStagesNamed(const std::vector<std::string>& names) {
  for (const auto& info : stageInfos_) {
    if (!plan_.available(info.spec.name) ||
        std::find(names.begin(), names.end(), info.spec.name) == names.end())
      continue;
    stages_.emplace_back(&info, info.create(preset_));
    ScopedTimer timer(&times_, info.spec.name + " (prepare)");
    stages_.back().second->prepare(context_);
  }
}

FrameContext RenderSession::readFrame(int64_t frameNumber) {
  FrameContext frame;
  frame.frame = frameNumber;
  frame.timeSeconds = double(frameNumber) / context_.fps;
  {
    ScopedTimer timer(&times_, "decode");
    frame.image = workingCodes_ ? reader_->readCodesThrough(frameNumber, *workingCodes_)
                                : reader_->read(frameNumber);
  }
  if (size_t bad = mayHoldNonFinite(clip()) ? ops::replaceNonFinite(frame.image) : 0) {
    log::warning(fmt::format("frame {}: {} NaN/Inf values in {} replaced by 0", frameNumber, bad,
                             clip().path));
  }
  if (!workingCodes_) {
    ScopedTimer timer(&times_, "colour in");
    toWorking_.apply(frame.image);
  }
  return frame;
}

void RenderSession::processFrame(FrameContext& frame) {
  // The lights', the glare's and the grading stages' AOV planes, when asked for, exist before the
  // stages run: those stages write them only when they are there (making four planes of a 1080p
  // frame costs more than ten lights). The others are made by their stages (the depth plane's
  // absence means sky).
  for (const std::string& aov : request_.aovs)
    if (aov == "lights" || aov == "glare" || isGradingAov(aov)) ensureAovPlanes(frame.image, {aov});
  // The rain layer's planes, when no AOV writes them out, are the rain renderer's scratch: the
  // last frame's are handed on rather than made and zeroed anew (41 MB at 1080p). Every path of
  // the renderer writes every pixel of them (the CPU rasteriser clears each tile it draws).
  const bool rainPlanesWritten =
      std::any_of(request_.aovs.begin(), request_.aovs.end(),
                  [](const std::string& aov) { return aov == "rain" || aov == "matte"; });
  if (!rainPlanesWritten)
    for (auto& [name, plane] : rainScratch_) frame.image.planes[name] = std::move(plane);
  for (auto& [name, stage] : frameStages_) {
    ScopedTimer timer(&times_, name);
    try {
      stage->process(context_, frame);
    } catch (const Error& e) {
      throw Error(e.what(), {name, frame.frame, e.context().file});
    } catch (const std::exception& e) {
      throw Error(e.what(), {name, frame.frame, {}});
    }
  }
  if (!frame.image.findPlane(kDepthPlane)) {
    frame.image.plane(kDepthPlane)
        .assign(frame.image.pixelCount(), std::numeric_limits<float>::infinity());
  }
  ensureAovPlanes(frame.image, request_.aovs);
  if (rainPlanesWritten) return;
  rainScratch_.clear();
  for (const char* name : {"rain.R", "rain.G", "rain.B", "rain.A", "matte"}) {
    auto found = frame.image.planes.find(name);
    if (found == frame.image.planes.end()) continue;
    rainScratch_.emplace(name, std::move(found->second));
    frame.image.planes.erase(found);
  }
}

void RenderSession::toOutput(Image& image) const {
  toOutput_.apply(image);
}

Plan planJob(const std::string& input, std::optional<int64_t> movieFirstFrame, const Preset& preset,
             const std::string& cacheDir, const std::vector<StageInfo>& stages, ClipInfo* clipOut) {
  auto reader = openNumberedClipWithCache(input, movieFirstFrame, cacheDir);
  std::optional<ArtifactCache> cache;
  if (!cacheDir.empty()) cache.emplace(cacheDir);
  const std::string framesKey = cache ? workingFramesKey(preset, reader->info()) : "";
  Plan plan = makePlan(preset, reader->info(), cache ? &*cache : nullptr, framesKey, stages);
  if (clipOut) *clipOut = reader->info();
  return plan;
}

RenderSummary renderJob(const RenderRequest& request, const Preset& preset,
                        const std::vector<StageInfo>& stageInfos, StageTimes& times) {
  // The output's folder before any work (and before the lock beside the frames).
  fs::ensureParentFolder(request.output.path, request.format.makeFolders);
  RenderSession session(request, preset, stageInfos, times);
  RenderSummary summary;
  summary.plan = session.plan();
  refuseSingleFileForManyFrames(request.output, session.frames());
  // Held until the last frame is written, --skip-existing's checks included.
  OutputLock lock(request.output, session.frames().front(), session.frames().back());
  if (int removed = lock.removeStaleTemporaries()) {
    log::info(fmt::format("removed {} temporary files left by renders that were killed", removed));
  }
  // Frames already on disk are skipped before any decoding.
  std::vector<int64_t> frames = session.frames();
  if (request.skipExisting) {
    FramesToRender todo =
        framesStillToRender(request.output, frames, session.writerOptions().metadata, request.aovs,
                            fmt::format("{}x{}", session.clip().width, session.clip().height));
    summary.framesSkipped = todo.kept;
    summary.framesRedone = todo.redone;
    if (todo.frames.empty()) return summary;
    frames = std::move(todo.frames);
  }
  session.prepareStages();
  summary.framesWritten = renderFrames(session, request, frames, times);
  return summary;
}

}  // namespace pluvia
