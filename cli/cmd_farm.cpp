// pluvia farm: a render split into chunks on a Slurm cluster (farm slurm), its state (farm
// status), and a movie output's last step (farm assemble). The work is in src/farm.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <thread>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "farm/assemble.h"
#include "farm/farm_job.h"
#include "farm/slurm.h"
#include "io/clip_reader.h"
#include "io/output_target.h"
#include "io/timecode.h"
#include "pipeline/camera_settings.h"
#include "pipeline/color_settings.h"
#include "pipeline/frame_metadata.h"
#include "pipeline/numbered_clip_reader.h"
#include "pipeline/render_job.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/executable.h"
#include "util/fs.h"
#include "util/interrupt.h"
#include "util/log.h"
#include "util/printable.h"
#include "util/timer.h"

namespace pluvia::cli {
namespace stdfs = std::filesystem;

namespace {

// Beside the output, named after it: out/rain.####.exr and out/rain.mp4 -> out/rain.farm.
std::string defaultFarmDir(const OutputTarget& output) {
  std::string name = output.pattern ? stdfs::path(output.pattern->prefix).filename().string()
                                    : stdfs::path(output.path).stem().string();
  while (!name.empty() && (name.back() == '.' || name.back() == '_')) name.pop_back();
  return (stdfs::path(output.path).parent_path() / ((name.empty() ? "pluvia" : name) + ".farm"))
      .string();
}

void addSlurmCommand(CLI::App* farm) {
  auto* cmd = farm->add_subcommand(
      "slurm",
      "write (and with --submit submit) a Slurm job: prepare, render chunks as a job array after "
      "it, and for a movie an assembly job after them");
  struct Args {
    std::string input, preset, output, frames, cache, farmDir, partition;
    std::vector<std::string> sets, sbatchArgs;
    RenderOutputOptions writes;
    int chunk = 0, threads = 0, cpus = 0;
    bool submit = false, dryRun = false;
    std::optional<int64_t> startFrame;
  };
  auto args = std::make_shared<Args>();
  addClipPresetOptions(cmd, args->input, args->preset, args->sets);
  cmd->add_option("-o,--output", args->output,
                  "sequence pattern (out.####.exr) or movie (out.mp4), on a disk every node sees")
      ->required();
  cmd->add_option("--chunk", args->chunk, "frames per render task")
      ->required()
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--frames", args->frames, "FIRST-LAST, in the clip's frame numbers (all)")
      ->check(nonEmptyText());
  cmd->add_option("--cache", args->cache,
                  "per-clip analysis cache every node sees (default: FARM_DIR/cache)");
  cmd->add_option("--farm-dir", args->farmDir,
                  "scripts, logs and task records (default: beside the output, NAME.farm)");
  cmd->add_option("--partition", args->partition, "Slurm partition");
  cmd->add_option("--cpus-per-task", args->cpus, "CPUs per job (default: the cluster's)");
  cmd->add_option("--sbatch-arg", args->sbatchArgs,
                  "another #SBATCH line for every job, e.g. --sbatch-arg=--time=2:00:00");
  cmd->add_option("--threads", args->threads,
                  "threads per chunk (default: --cpus-per-task, else the node's Slurm allocation)")
      ->check(CLI::Range(1, 64));
  addRenderOutputOptions(cmd, args->writes);
  addStartFrameOption(cmd, args->startFrame);
  auto* submit = cmd->add_flag("--submit", args->submit, "submit the jobs through sbatch");
  cmd->add_flag("--dry-run", args->dryRun, "print the scripts, write and submit nothing")
      ->excludes(submit);
  cmd->callback([=] {
    checkProxyScale(args->writes.proxy);
    args->writes.refuseOptionsNotFor(args->output);
    const OutputTarget output = OutputTarget::classify(stdfs::absolute(args->output).string());
    // An unknown AOV refused here, not on the farm; a farm movie is assembled from the chunks'
    // beauty frames alone, so its AOVs would be lost.
    if (!args->writes.aovs().empty() && output.isMovie())
      throw UsageError(
          fmt::format("--aov {}: a farm render assembles the movie {} from its "
                      "frames without their AOVs; render an image sequence such as "
                      "out.####.exr, whose AOVs the chunks write",
                      fmt::join(args->writes.aovs(), ","), args->output));
    const Preset preset = loadPreset(args->preset, args->sets);  // refused here, not on the farm
    const std::unique_ptr<ClipReader> reader = openNumberedClip(args->input, args->startFrame);
    const ClipInfo& clip = reader->info();
    farm::FarmJob job;
    job.pluvia = executablePath().string();
    if (job.pluvia.empty())
      throw Error("cannot find pluvia's own binary for the farm's tasks (/proc/self/exe)");
    job.input = stdfs::absolute(args->input).string();
    job.preset =
        stdfs::exists(args->preset) ? stdfs::absolute(args->preset).string() : args->preset;
    job.sets = args->sets;
    job.output = output;
    // Made here, as a local render makes it (--mkdir for more than its last level): a chunk
    // never finds it missing, and a mistyped path fails at submission, not on the farm.
    fs::ensureParentFolder(job.output.path, args->writes.makeFolders ? fs::MakeFolders::All
                                                                     : fs::MakeFolders::LastLevel);
    job.farmDir =
        stdfs::absolute(args->farmDir.empty() ? defaultFarmDir(output) : args->farmDir).string();
    job.workingDir = stdfs::current_path().string();
    job.cacheDir =
        stdfs::absolute(args->cache.empty() ? (stdfs::path(job.farmDir) / "cache").string()
                                            : args->cache)
            .string();
    job.firstFrame = clip.frames.front();
    job.lastFrame = clip.frames.back();
    if (!args->frames.empty()) {
      std::tie(job.firstFrame, job.lastFrame) = parseFrameRange(args->frames);
      if (job.firstFrame < clip.frames.front() || job.lastFrame > clip.frames.back())
        throw UsageError(fmt::format("--frames {}: {} has frames {}-{}", args->frames, clip.path,
                                     clip.frames.front(), clip.frames.back()));
    }
    if (job.firstFrame < 0)
      throw UsageError(
          fmt::format("--frames {}: a farm job renders frames 0 and up", args->frames));
    job.chunkFrames = args->chunk;
    job.fps = cameraSettings(preset).framesPerSecondOf(clip.fps);
    job.threads = args->threads > 0 ? args->threads : args->cpus;
    // Every render option goes to the chunks, a movie's codec to its assembly instead (the
    // chunks write TIFF), and the proxy also to the prepare job.
    const bool movie = output.isMovie();
    for (const std::string& argument : args->writes.renderArguments())
      job.renderOptions.push_back(argument);
    if (movie && args->writes.codec != RenderOutputOptions().codec) {
      const auto codec = std::find(job.renderOptions.begin(), job.renderOptions.end(), "--codec");
      job.renderOptions.erase(codec, codec + 2);
      job.assembleOptions = {"--codec", args->writes.codec};
    }
    if (args->writes.proxy != 1.0)
      job.prepareOptions = {"--proxy", fmt::format("{}", args->writes.proxy)};
    // The prepare job and the chunks number the movie's frames as this job does.
    if (args->startFrame)
      for (auto* options : {&job.prepareOptions, &job.renderOptions})
        options->insert(options->end(), {"--start-frame", std::to_string(*args->startFrame)});
    // The plate's timecode, counted on to the job's first frame, as a local render's movie has it.
    if (const auto tc = clip.metadata.find("smpte:TimeCode"); movie && tc != clip.metadata.end())
      if (const auto start = Timecode::parse(tc->second, job.fps))
        job.assembleOptions.insert(
            job.assembleOptions.end(),
            {"--timecode", start->plus(job.firstFrame - clip.frames.front()).text()});
    // The chunks write their frames in the space a tagged movie plate came in (a BT.709 plate
    // stays BT.709): the assembly tags the movie with it, as a local render would.
    if (const auto tagged = taggedInputSpace(colorSettings(preset), clip);
        movie && tagged && colorSettings(preset).outputSpace == "auto") {
      job.assembleOptions.insert(job.assembleOptions.end(), {"--colorspace", *tagged});
    }
    if (const char* ocio = std::getenv("OCIO"); ocio && *ocio)
      job.ocioConfig = stdfs::absolute(ocio).string();
    // The chunks' outputs must not be the plate's files (the render refuses it too, but only on
    // the farm, after the prepare job).
    std::vector<std::string> outputs{output.path};
    if (output.isSequence())
      for (int64_t f = job.firstFrame; f <= job.lastFrame; ++f)
        outputs.push_back(output.pathFor(f));
    refuseOverwritingInput(clip.files, "-o", outputs);

    farm::SlurmOptions options;
    options.partition = args->partition;
    options.cpusPerTask = args->cpus;
    options.sbatchArgs = args->sbatchArgs;
    const auto scripts = farm::slurmScripts(job, options);
    const std::string summary =
        fmt::format("{} frames {}-{} in {} chunks of {} -> {}", job.input, job.firstFrame,
                    job.lastFrame, farm::chunkCount(job), job.chunkFrames, job.output.path);
    if (args->dryRun) {
      for (const auto& script : scripts)
        std::cout << fmt::format("==> {}/{} <==\n{}\n", job.farmDir, script.name, script.text);
      log::info("dry run, nothing written: " + summary);
      return;
    }
    farm::writeSlurmFarmFolder(job, scripts);
    if (!args->submit) {
      log::info(fmt::format("wrote the Slurm job to {} ({}); submit it with {}/submit.sh",
                            job.farmDir, summary, job.farmDir));
      return;
    }
    const farm::SlurmJobIds ids = farm::submitSlurm(job);
    std::cout << fmt::format("prepare job {}\nrender job array {} ({} tasks, after {})\n",
                             ids.prepare, ids.render, farm::chunkCount(job), ids.prepare);
    if (!ids.assemble.empty())
      std::cout << fmt::format("assemble job {} (after {})\n", ids.assemble, ids.render);
    log::info(fmt::format("submitted {}; see `pluvia farm status {}`", summary, job.farmDir));
  });
}

void addStatusCommand(CLI::App* farm, Invocation& invocation) {
  auto* cmd = farm->add_subcommand(
      "status",
      "the state of a farm job's jobs and tasks (squeue, sacct, task records); exit 1 "
      "when a task failed, 3 when the failed tasks only ran out of time");
  struct Args {
    std::string farmDir;
    bool wait = false;
    double timeout = 0;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("FARM_DIR", args->farmDir, "the farm job's folder")->required();
  cmd->add_flag("--wait", args->wait, "wait until every job has ended");
  cmd->add_option("--timeout", args->timeout, "with --wait: give up after this many seconds");
  cmd->callback([=, &invocation] {
    InterruptHandlers stopCleanly;
    const auto started = std::chrono::steady_clock::now();
    farm::FarmStatus status = farm::slurmStatus(args->farmDir);
    while (args->wait && !status.finished) {
      if (args->timeout > 0 && secondsSince(started) > args->timeout) {
        std::cout << printable(status.text, /*keepLines=*/true);
        throw Error(fmt::format("the farm job in {} has not ended after {:g} s", args->farmDir,
                                args->timeout),
                    {"farm", {}, args->farmDir});
      }
      throwIfInterrupted();
      std::this_thread::sleep_for(std::chrono::seconds(1));
      status = farm::slurmStatus(args->farmDir);
    }
    // A task record's host or reason is the node's text: no escape sequence reaches the terminal.
    std::cout << printable(status.text, /*keepLines=*/true);
    // 3 when every failed task only ran out of time (resubmit it with more), 1 for a failure.
    if (status.failed) invocation.exitCode = status.timedOut == status.failed ? 3 : 1;
  });
}

void addResubmitCommand(CLI::App* farm) {
  auto* cmd = farm->add_subcommand(
      "resubmit",
      "submit again only the failed or missing tasks of an ended farm job (then its assembly); "
      "their frames already written are kept (--skip-existing)");
  auto farmDir = std::make_shared<std::string>();
  cmd->add_option("FARM_DIR", *farmDir, "the farm job's folder")->required();
  cmd->callback([=] {
    const std::string submitted = farm::resubmitSlurm(*farmDir);
    if (submitted.empty())
      log::info(fmt::format("nothing failed in {}: nothing to resubmit", *farmDir));
    else
      log::info(fmt::format("resubmitted {}; see `pluvia farm status {}`", submitted, *farmDir));
  });
}

void addAssembleCommand(CLI::App* farm) {
  auto* cmd = farm->add_subcommand(
      "assemble", "encode a farm job's rendered frames into its movie (the assembly job)");
  struct Args {
    std::string frames, output, preset, range, codec = RenderOutputOptions().codec, colorSpace,
                                               timecode;
    std::vector<std::string> sets;
    double fps = 24;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("FRAMES", args->frames, "the chunks' frames (frames.####.tif)")->required();
  cmd->add_option("--codec", args->codec, "the render's movie codec (see pluvia render --help)");
  cmd->add_option("-o,--output", args->output, "the movie (out.mp4)")->required();
  cmd->add_option("--fps", args->fps, "frames per second, 0.001 to 10000")
      ->required()
      ->check(CLI::Range(0.001, 10000.0));
  cmd->add_option("--frames", args->range, "FIRST-LAST")->required();
  cmd->add_option("-p,--preset", args->preset, "the render's preset, recorded in the movie")
      ->required();
  cmd->add_option("--set", args->sets, "the render's overrides");
  cmd->add_option("--timecode", args->timecode,
                  "the plate's timecode at frame FIRST (HH:MM:SS:FF), carried into the movie");
  cmd->add_option("--colorspace", args->colorSpace,
                  "the colour space the chunks' frames are in, when the render took it from the "
                  "plate's tags (default: as the render resolves color.output)");
  cmd->callback([=] {
    const auto [first, last] = parseFrameRange(args->range);
    const Preset preset = loadPreset(args->preset, args->sets);
    WriterOptions options;
    options.fps = args->fps;
    options.metadata = frameMetadata(preset, allStages());
    options.color = outputColorTags(
        colorSettings(preset), args->output,
        args->colorSpace.empty() ? std::nullopt : std::optional<std::string>(args->colorSpace));
    options.codec = args->codec;
    if (!args->timecode.empty()) {
      options.timecode = Timecode::parse(args->timecode, args->fps);
      if (!options.timecode)
        throw UsageError(
            fmt::format("--timecode {}: not HH:MM:SS:FF at {:g} fps", args->timecode, args->fps));
      options.firstFrame = first;
    }
    InterruptHandlers stopCleanly;
    const auto started = std::chrono::steady_clock::now();
    const int frames = farm::assembleMovie(args->frames, first, last,
                                           OutputTarget::classify(args->output), options);
    log::info(fmt::format("encoded {} frames into {} in {:.1f} s", frames, args->output,
                          secondsSince(started)));
  });
}

}  // namespace

void addFarmCommand(CLI::App& app, Invocation& invocation) {
  auto* farm = app.add_subcommand("farm", "render on a farm: Slurm jobs, their state, assembly");
  farm->require_subcommand(1);
  addSlurmCommand(farm);
  addStatusCommand(farm, invocation);
  addResubmitCommand(farm);
  addAssembleCommand(farm);
}

}  // namespace pluvia::cli
