// `pluvia bench`: frames per second of a full render split by stage, against ffmpeg's own
// decode + encode of the same clip with the same encoder settings, measured in the same run.
#include <unistd.h>

#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "pipeline/render_job.h"
#include "pluvia/version.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/log.h"
#include "util/subprocess.h"

namespace pluvia::cli {
namespace stdfs = std::filesystem;

namespace {

// The bundled example scaled to 1920x1080 when no clip is given.
std::string makeBenchClip(const stdfs::path& folder, int frames) {
  stdfs::path example =
      stdfs::path(kSourcePresetDir).parent_path() / "examples/street/street_plate.mp4";
  if (!stdfs::exists(example))
    throw UsageError("give a clip to bench: the bundled example was not found at " +
                     example.string());
  stdfs::path clip = folder / "bench_1080p.mp4";
  auto r = runProcess({"ffmpeg", "-y", "-v", "error", "-i", example.string(), "-frames:v",
                       std::to_string(frames), "-vf", "scale=1920:1080", "-c:v", "libx264",
                       "-preset", "veryfast", "-crf", "18", clip.string()});
  if (r.exitCode != 0) throw Error("ffmpeg could not make the benchmark clip: " + r.output);
  return clip.string();
}

}  // namespace

void addBenchCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand(
      "bench", "benchmark a render against ffmpeg's decode+encode of the same clip");
  struct Args {
    std::string input, preset = "moderate";
    std::vector<std::string> sets;
    int frames = 48;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("INPUT", args->input, "clip to bench; default: the example scaled to 1080p");
  cmd->add_option("-p,--preset", args->preset, "preset name or path");
  cmd->add_option("--set", args->sets, "override KEY=VALUE");
  cmd->add_option("--frames", args->frames, "frames to render")->check(CLI::Range(1, 100000));
  cmd->callback([=, &invocation] {
    stdfs::path folder = stdfs::temp_directory_path() / fmt::format("pluvia-bench-{}", ::getpid());
    stdfs::create_directories(folder);
    std::string input = args->input.empty() ? makeBenchClip(folder, args->frames) : args->input;
    Preset preset = loadPreset(args->preset, args->sets);

    // ffmpeg alone: decode and encode with the settings pluvia's movie writer uses.
    auto started = std::chrono::steady_clock::now();
    auto r =
        runProcess({"ffmpeg", "-y", "-v", "error", "-i", input, "-frames:v",
                    std::to_string(args->frames), "-c:v", "libx264", "-preset", "medium", "-crf",
                    "16", "-pix_fmt", "yuv420p", (folder / "ffmpeg_passthrough.mp4").string()});
    const double ffmpegSeconds = secondsSince(started);
    if (r.exitCode != 0) throw Error("ffmpeg passthrough failed: " + r.output);

    RenderRequest request;
    request.input = input;
    request.output = (folder / "pluvia_render.mp4").string();
    request.commandLine = invocation.commandLine;
    request.progress = false;
    StageTimes times;
    auto log = log::level();
    log::setLevel(log::Level::Warning);
    started = std::chrono::steady_clock::now();
    RenderSummary summary;
    try {
      ClipInfo clip;
      planJob(input, preset, "", allStages(), &clip);
      request.lastFrame = clip.frames.front() + args->frames - 1;
      summary = renderJob(request, preset, allStages(), times);
    } catch (...) {
      log::setLevel(log);
      stdfs::remove_all(folder);
      throw;
    }
    const double pluviaSeconds = secondsSince(started);
    log::setLevel(log);
    const int frames = summary.framesWritten;

    std::cout << fmt::format("bench: {} frames of {} with preset {}\n", frames, input,
                             preset.source());
    std::cout << fmt::format("{:<22} {:>10} {:>10}\n", "stage", "ms/frame", "frames/s");
    for (const auto& [stage, entry] : times.snapshot()) {
      const double ms = 1000.0 * entry.first / std::max(1, frames);
      if (stage.ends_with("(prepare)")) {
        // Once per clip: its total, not a per-frame rate.
        std::cout << fmt::format("{:<22} {:>10.2f} ms once\n", stage, 1000.0 * entry.first);
        continue;
      }
      std::cout << fmt::format("{:<22} {:>10.2f} {:>10.1f}\n", stage, ms,
                               ms > 0 ? 1000.0 / ms : 0.0);
    }
    const double pluviaFps = frames / pluviaSeconds;
    const double ffmpegFps = args->frames / ffmpegSeconds;
    std::cout << fmt::format("pluvia end to end:      {:.2f} frames/s ({:.1f} s)\n", pluviaFps,
                             pluviaSeconds);
    std::cout << fmt::format("ffmpeg decode+encode:   {:.2f} frames/s ({:.1f} s)\n", ffmpegFps,
                             ffmpegSeconds);
    std::cout << fmt::format("ratio pluvia / ffmpeg:  {:.3f}\n", pluviaFps / ffmpegFps);
    std::cout << "(stage times overlap: decode and encode run on their own threads)\n";
    stdfs::remove_all(folder);
  });
}

}  // namespace pluvia::cli
