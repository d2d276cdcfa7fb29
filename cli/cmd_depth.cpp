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
#include "io/output_target.h"
#include "io/sequence_pattern.h"
#include "pipeline/camera_settings.h"
#include "pluvia/version.h"
#include "sfm/clip_tracking.h"
#include "stages/depth_settings.h"
#include "stages/depth_tracking.h"
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

// Depth from a COLMAP reconstruction of the selected frames (sfm/clip_tracking.h), run in
// OUTPUT_FOLDER/colmap (its log: colmap/colmap.log), or read from depth.colmap_model; the poses
// are scaled by camera.height_m over the fitted ground plane (depth.scale). Writes the depth EXRs
// (from depth.colmap_dense's maps where given) and OUTPUT_FOLDER/colmap/poses.json.
void writeColmapDepth(ClipReader& reader, const std::vector<int64_t>& frames,
                      const std::vector<std::string>& outputs, const Preset& preset,
                      const Metadata& metadata) {
  const ClipInfo& clip = reader.info();
  const DepthSettings depth = depthSettings(preset);
  sfm::ClipTrackingSettings settings = depthTrackingSettings(depth, cameraSettings(preset));
  settings.workspace = std::filesystem::absolute(outputs.front()).parent_path() / "colmap";
  const std::string& model = depth.colmapModel;
  sfm::SfmReconstruction reconstruction;
  std::string log;
  if (model.empty()) {
    sfm::ClipTracking tracking = sfm::trackClip(
        frames, [&reader](int64_t f) { return reader.read(f); }, settings);
    reconstruction = std::move(tracking.sfm);
    if (!tracking.run.logPath.empty()) log = " (COLMAP log: " + tracking.run.logPath.string() + ")";
  } else {
    // The whole clip's frames, so that --frames may select frames between registered ones.
    reconstruction = sfm::trackingFromModel(
        model, clip.frames, clip.isMovie ? std::vector<std::string>{} : clip.files, settings.sfm);
    log = " (depth.colmap_model: " + model + ")";
  }
  if (!reconstruction.ok())
    throw Error(fmt::format("{}{}; use --source layers for this clip", reconstruction.message, log),
                {"depth", {}, clip.path});
  log::info(fmt::format("colmap: {} of {} frames registered, {:.2f} px mean reprojection error{}",
                        reconstruction.registeredCount, reconstruction.frameCount,
                        reconstruction.meanReprojectionErrorPx,
                        reconstruction.message.empty() ? "" : "; " + reconstruction.message));
  for (size_t i = 0; i < frames.size(); ++i) {
    const std::vector<float> depthMeters =
        sfm::colmapFrameDepth(reconstruction, frames[i], reader.read(frames[i]), depth.colmapDense);
    writeImageFile(outputs[i], clip.width, clip.height, {{"Z", depthMeters.data(), 1, true}},
                   metadata, frames[i]);
  }
  std::filesystem::create_directories(settings.workspace);
  fs::writeTextFile(settings.workspace / "poses.json",
                    sfm::posesJson(reconstruction, frames).dump(2) + "\n");
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
  cmd->add_option("--frames", args->frames, "FIRST-LAST, in the clip's frame numbers")
      ->check(nonEmptyText());
  cmd->callback([=, &invocation] {
    const OutputTarget output = OutputTarget::classify(args->output);
    if (!output.isSequence() || lowerExtension(output.path) != "exr")
      throw UsageError(fmt::format("-o {}: expected an EXR sequence pattern such as depth.####.exr",
                                   args->output));
    // Everything that can be refused is refused before the first file is written.
    Preset preset = loadPreset(args->preset, args->sets);
    auto reader = openClip(args->input);
    const ClipInfo& clip = reader->info();
    const std::vector<int64_t> frames = selectFrames(clip, args->frames);
    std::vector<std::string> outputs;
    for (int64_t f : frames) outputs.push_back(output.pathFor(f));
    std::vector<std::string> inputs = clip.files;
    inputs.push_back(clip.path);
    refuseOverwritingInput(inputs, "-o", outputs);
    const std::filesystem::path folder = std::filesystem::absolute(outputs.front()).parent_path();
    if (!std::filesystem::is_directory(folder))
      throw UsageError(
          fmt::format("-o {}: the folder {} does not exist", args->output, folder.string()));

    const Metadata metadata{{"pluvia:version", kVersion},
                            {"pluvia:presetHash", preset.hash()},
                            {"pluvia:commandLine", invocation.commandLine}};
    if (args->source == "colmap") {
      writeColmapDepth(*reader, frames, outputs, preset, metadata);
      log::info(fmt::format("wrote {} depth frames to {}", frames.size(), args->output));
      return;
    }

    // The camera the render builds (pipeline/render_job.cpp), moved along camera.path.
    const CameraSettings camera = cameraSettings(preset);
    const CameraPath path = camera.path(camera.base(clip.width, clip.height));
    const nlohmann::json layers = depthSettings(preset).layers;
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
