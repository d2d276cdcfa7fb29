// `pluvia depth`: one single-channel float EXR of z-depth per frame (channel "Z", metres, +inf
// for sky): from the preset's manual layers (what the render's depth stage uses), or from a
// COLMAP reconstruction of the clip with its camera poses (poses.json) beside the frames.
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "geometry/camera.h"
#include "geometry/depth_layers.h"
#include "io/clip_reader.h"
#include "io/image_file_writer.h"
#include "io/sequence_pattern.h"
#include "pluvia/version.h"
#include "preset/camera_path_preset.h"
#include "sfm/colmap_model.h"
#include "sfm/colmap_runner.h"
#include "sfm/sfm_poses.h"
#include "sfm/sparse_densify.h"
#include "util/error.h"
#include "util/fs.h"
#include "util/log.h"

namespace pluvia::cli {
namespace {

// The clip's frames within --frames; a range that leaves the clip is an error before any write.
std::vector<int64_t> selectFrames(const ClipInfo& clip, const std::string& range) {
  if (range.empty()) return clip.frames;
  auto [first, last] = parseFrameRange(range);
  std::vector<int64_t> frames;
  std::set<int64_t> available(clip.frames.begin(), clip.frames.end());
  for (int64_t f = first; f <= last; ++f) {
    if (!available.count(f))
      throw UsageError(fmt::format("--frames {}: frame {} is not in {} (it has frames {}-{})",
                                   range, f, clip.path, clip.frames.front(), clip.frames.back()),
                       {"read", f, clip.path});
    frames.push_back(f);
  }
  return frames;
}

using Metadata = std::map<std::string, std::string>;

// The registered frame nearest to `frame`: its sparse points are the ones a frame between
// keyframes most likely sees (points hidden from every nearby view are left out).
const SfmKeyframe& nearestKeyframe(const SfmReconstruction& sfm, int64_t frame) {
  const SfmKeyframe* best = &sfm.keyframes.front();
  for (const SfmKeyframe& key : sfm.keyframes)
    if (std::llabs(key.frame - frame) < std::llabs(best->frame - frame)) best = &key;
  return *best;
}

nlohmann::json posesJson(const SfmReconstruction& sfm, const std::vector<int64_t>& frames) {
  nlohmann::json poses = nlohmann::json::array();
  std::set<int64_t> registered;
  for (const SfmKeyframe& key : sfm.keyframes) registered.insert(key.frame);
  for (int64_t frame : frames) {
    const Camera camera = sfm.path.cameraAt(static_cast<double>(frame));
    const Eigen::Quaterniond q(camera.worldFromCamera);
    poses.push_back(
        {{"frame", frame},
         {"registered", registered.count(frame) > 0},
         {"position_m",
          {camera.positionMeters.x(), camera.positionMeters.y(), camera.positionMeters.z()}},
         {"world_from_camera_wxyz", {q.w(), q.x(), q.y(), q.z()}},
         {"focal_px", camera.focalPx},
         {"principal_point_px", {camera.cx, camera.cy}}});
  }
  return {{"convention", "pluvia: metres, +Y up, camera looks down -Z, ground at y = 0"},
          {"registered_fraction", sfm.registeredFraction},
          {"mean_reprojection_error_px", sfm.meanReprojectionErrorPx},
          {"baseline_over_depth", sfm.baselineOverDepth},
          {"note", sfm.message},
          {"frames", poses}};
}

// Depth from a COLMAP reconstruction of the selected frames (src/sfm). The frames go to
// OUTPUT_FOLDER/colmap/frames as 8-bit PNG and COLMAP runs in OUTPUT_FOLDER/colmap (its log:
// colmap/colmap.log); the poses are scaled by camera.height_m over the fitted ground plane; each
// frame's sparse points are densified, edge-aware, guided by the frame. Writes the depth EXRs and
// OUTPUT_FOLDER/colmap/poses.json.
void writeColmapDepth(ClipReader& reader, const std::vector<int64_t>& frames,
                      const std::vector<std::string>& outputs, const Preset& preset,
                      const Metadata& metadata) {
  const ClipInfo& clip = reader.info();
  const std::filesystem::path workspace =
      std::filesystem::absolute(outputs.front()).parent_path() / "colmap";
  std::filesystem::create_directories(workspace / "frames");
  ColmapRequest request;
  request.workspace = workspace;
  std::map<std::string, int64_t> frameOfImage;
  for (int64_t frame : frames) {
    const Image image = reader.read(frame);
    const std::string name = fmt::format("frame_{:08d}.png", frame);
    const std::filesystem::path path = workspace / "frames" / name;
    const float* rgba = image.rgba.data();
    writeImageFile(path.string(), image.width, image.height,
                   {{"R", rgba, 4}, {"G", rgba + 1, 4}, {"B", rgba + 2, 4}}, {}, frame);
    request.images.push_back(path);
    frameOfImage[name] = frame;
  }
  request.initialFocalPx =
      Camera::fromFieldOfView(clip.width, clip.height, preset.number("camera.fov_deg"), 0.0, 0.0)
          .focalPx;
  const ColmapRun run = runColmapSparse(request);
  SfmOptions options;
  options.scale.cameraHeightMeters = preset.number("camera.height_m");
  const SfmReconstruction sfm =
      reconstructionFromColmap(readColmapTextModel(run.modelFolder), frameOfImage, options);
  if (sfm.status == SfmStatus::TooFewRegistered || sfm.status == SfmStatus::NoParallax)
    throw Error(fmt::format("{}; use --source layers for this clip (COLMAP log: {})", sfm.message,
                            run.logPath.string()),
                {"depth", {}, clip.path});
  log::info(fmt::format("colmap: {} of {} frames registered, {:.2f} px mean reprojection error{}",
                        sfm.registeredCount, sfm.frameCount, sfm.meanReprojectionErrorPx,
                        sfm.message.empty() ? "" : "; " + sfm.message));
  for (size_t i = 0; i < frames.size(); ++i) {
    const Camera camera = sfm.path.cameraAt(static_cast<double>(frames[i]));
    const auto samples = projectSparsePoints(camera, sfm.pointsMeters,
                                             &nearestKeyframe(sfm, frames[i]).visiblePoints);
    const std::vector<float> depth = densifySparseDepth(samples, reader.read(frames[i]));
    writeImageFile(outputs[i], clip.width, clip.height, {{"Z", depth.data(), 1, true}}, metadata,
                   frames[i]);
  }
  fs::writeTextFile(workspace / "poses.json", posesJson(sfm, frames).dump(2) + "\n");
}

}  // namespace

void addDepthCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand(
      "depth", "write the scene depth per frame (metres, +inf for sky) as single-channel EXRs");
  struct Args {
    std::string input, output, preset = "base", source = "layers", frames;
    std::vector<std::string> sets;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("INPUT", args->input, "movie, image sequence or image (its size and frames)")
      ->required();
  cmd->add_option("-o,--output", args->output, "EXR sequence pattern, e.g. depth.####.exr")
      ->required();
  cmd->add_option("--source", args->source, "layers (the preset's depth.layers) or colmap")
      ->check(CLI::IsMember({"layers", "colmap"}));
  cmd->add_option("-p,--preset", args->preset, "preset name or path (camera and depth.layers)");
  cmd->add_option("--set", args->sets, "override KEY=VALUE (e.g. depth.layers.1.distance_m=40)");
  cmd->add_option("--frames", args->frames, "FIRST-LAST, in the clip's frame numbers");
  cmd->callback([=, &invocation] {
    auto pattern = SequencePattern::parse(args->output);
    if (!pattern || lowerExtension(args->output) != "exr")
      throw UsageError(fmt::format("-o {}: expected an EXR sequence pattern such as depth.####.exr",
                                   args->output));
    // Everything that can be refused is refused before the first file is written.
    Preset preset = loadPreset(args->preset, args->sets);
    auto reader = openClip(args->input);
    const ClipInfo& clip = reader->info();
    const std::vector<int64_t> frames = selectFrames(clip, args->frames);
    std::vector<std::string> outputs;
    for (int64_t f : frames) outputs.push_back(pattern->pathFor(f));
    std::vector<std::string> inputs = clip.files;
    inputs.push_back(clip.path);
    refuseOverwritingInput(inputs, "-o", outputs);

    const Metadata metadata{{"pluvia:version", kVersion},
                            {"pluvia:presetHash", preset.hash()},
                            {"pluvia:commandLine", invocation.commandLine}};
    if (args->source == "colmap") {
      writeColmapDepth(*reader, frames, outputs, preset, metadata);
      log::info(fmt::format("wrote {} depth frames to {}", frames.size(), args->output));
      return;
    }

    // The camera the render builds (pipeline/render_job.cpp), moved along camera.path.
    const Camera base =
        Camera::fromFieldOfView(clip.width, clip.height, preset.number("camera.fov_deg"),
                                preset.number("camera.tilt_deg"), preset.number("camera.height_m"));
    const CameraPath path = cameraPathFromPreset(preset, base);
    const nlohmann::json& layers = preset.at("depth.layers");
    const KeyedNumberAt rampAt = [](const nlohmann::json& v, double f) {
      return Ramp::fromJson(v).valueAt(f);
    };
    const bool perFrame = depthLayersAnimated(layers) || path.moving();
    std::vector<float> depth;
    for (size_t i = 0; i < frames.size(); ++i) {
      const double frame = static_cast<double>(frames[i]);
      try {
        if (perFrame || i == 0)
          depth = rasterizeDepthLayers(path.cameraAt(frame), layers, frame, rampAt);
      } catch (const Error& e) {
        throw Error(fmt::format("{} (preset {})", e.what(), preset.source()),
                    {"depth", frames[i], preset.source()});
      }
      // writeImageFile writes a temporary file and renames it: no partial EXR on failure.
      writeImageFile(outputs[i], clip.width, clip.height, {{"Z", depth.data(), 1, true}}, metadata,
                     frames[i]);
    }
    log::info(fmt::format("wrote {} depth frames to {}", frames.size(), args->output));
  });
}

}  // namespace pluvia::cli
