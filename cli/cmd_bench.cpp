// `pluvia bench`: frames per second of a full render split by stage, against ffmpeg's own
// decode + encode of the same clip with the same encoder settings, measured in the same run.
// `pluvia bench --strokes 10000,...,80000`: the GPU rain insertion alone (Table 3 of Wang et al.):
// frames per second of RainRenderer::render alone (cli/bench_strokes.h).
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <random>

#include <fmt/format.h>

#include "bench_day.h"
#include "bench_drops.h"
#include "bench_floors.h"
#include "bench_lod.h"
#include "bench_lookdev.h"
#include "bench_strokes.h"
#include "bench_timing.h"
#include "commands.h"
#include "common.h"
#include "image/color.h"
#include "image/ops.h"
#include "io/clip_reader.h"
#include "pipeline/render_job.h"
#include "rain/stroke_library.h"
#include "stages/registry.h"
#include "temporary_folder.h"
#include "util/error.h"
#include "util/fs.h"
#include "util/log.h"
#include "util/subprocess.h"
#include "util/thread_limit.h"

namespace pluvia::cli {
namespace stdfs = std::filesystem;

namespace {

// The bundled example scaled to 1920x1080 when no clip is given.
std::string makeBenchClip(const stdfs::path& folder, int frames) {
  const std::string example = findBesideInstall("examples/street/street_plate.mp4");
  if (example.empty())
    throw UsageError(
        "give a clip to bench: the bundled example examples/street/street_plate.mp4 is neither "
        "beside the install prefix nor in the current directory");
  stdfs::path clip = folder / "bench_1080p.mp4";
  auto r = runProcess({"ffmpeg", "-y", "-v", "error", "-i", example, "-frames:v",
                       std::to_string(frames), "-vf", "scale=1920:1080", "-c:v", "libx264",
                       "-preset", "veryfast", "-crf", "18", clip.string()});
  if (r.exitCode != 0) throw Error("ffmpeg could not make the benchmark clip: " + r.output);
  return clip.string();
}

// CPU seconds of this process and of its children that have been waited for (ffmpeg's encoder
// and decoder once closed): the work a run costs, which a machine shared with other jobs
// changes less than the wall time.
double cpuSecondsWithChildren() {
  auto seconds = [](int who) {
    rusage usage{};
    getrusage(who, &usage);
    auto of = [](const timeval& t) {
      return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
    };
    return of(usage.ru_utime) + of(usage.ru_stime);
  };
  return seconds(RUSAGE_SELF) + seconds(RUSAGE_CHILDREN);
}

// One movie render of the bench, timed: wall and CPU seconds (its ffmpeg decoder and encoder
// included) and the stages' split.
struct MovieRun {
  RenderRequest request;
  StageTimes times;
  double seconds = 0.0, cpuSeconds = 0.0;
  int64_t firstFrame = 0;
  int frames = 0;
};

// Renders the first `frames` frames of `input` to `output` with --cache `cacheDir` into `run`;
// `ycbcrCopy` (when given) keeps the Y'CbCr piped to x264, for the encoder's floor. Quiet below
// warnings.
void renderBenchMovie(MovieRun& run, const std::string& input, const Preset& preset, int frames,
                      const stdfs::path& output, const stdfs::path& ycbcrCopy,
                      const std::string& cacheDir, const std::string& commandLine) {
  run.request.input = input;
  run.request.output = OutputTarget::classify(output.string());
  run.request.commandLine = commandLine;
  run.request.progress = false;
  run.request.cacheDir = cacheDir;
  run.request.format.ycbcrCopy = ycbcrCopy.string();
  const auto level = log::level();
  log::setLevel(log::Level::Warning);
  const auto started = std::chrono::steady_clock::now();
  const double cpuStarted = cpuSecondsWithChildren();
  try {
    ClipInfo clip;
    planJob(input, std::nullopt, preset, "", allStages(), &clip);
    run.firstFrame = clip.frames.front();
    run.request.lastFrame = run.firstFrame + frames - 1;
    run.frames = renderJob(run.request, preset, allStages(), run.times).framesWritten;
  } catch (...) {
    log::setLevel(level);
    throw;
  }
  run.seconds = secondsSince(started);
  run.cpuSeconds = cpuSecondsWithChildren() - cpuStarted;
  log::setLevel(level);
}

// The atlas as pluvia-bench-strokes reads it; an existing file is left alone.
void saveAtlasJson(const rain::StrokeAtlas& atlas, const std::string& path) {
  if (stdfs::exists(path))
    throw UsageError(fmt::format("--save-atlas {}: the file exists; give a new name", path));
  const std::string text = rain::strokeAtlasToJson(atlas).dump();
  fs::writeFileAtomically(path, text.data(), text.size());
}

// The per-pixel passes of a render on one frame of `size`: colour in (sRGB to linear), darken,
// blur, fog, colour out (linear to sRGB) with the `moderate` preset's settings, each timed
// `frames` times (median wall and process CPU time, after one warm-up), and their sum.
void runPassBench(const std::string& size, int frames) {
  const auto [width, height] = parseFrameSize(size, 1, "720x480");
  Image plate(width, height);
  std::mt19937 random(3);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (size_t i = 0; i < plate.pixelCount(); ++i) {
    for (int c = 0; c < 3; ++c) plate.rgba[i * 4 + c] = std::round(255.0f * unit(random)) / 255.0f;
  }
  std::vector<float>& depth = plate.plane(kDepthPlane);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      depth[static_cast<size_t>(y) * width + x] =
          y < height / 3 ? INFINITY : 20.0f * static_cast<float>(height) / (3.0f * y - height + 3);
    }
  }
  const ColorConverter toLinear("sRGB", "linear-rec709"), toSrgb("linear-rec709", "sRGB");
  struct Pass {
    const char* name;
    std::function<void(Image&)> run;
  };
  const std::vector<Pass> passes = {
      {"colour in", [&](Image& i) { toLinear.apply(i); }},
      {"darken", [](Image& i) { ops::darken(i, 0.2f, 0.5f); }},
      {"blur", [](Image& i) { ops::gaussianBlur(i, 0.4f); }},
      {"fog",
       [](Image& i) {
         ops::fog(i, 0.0015f, {0.6f, 0.65f, 0.7f}, 2000.0f);
       }},
      {"colour out", [&](Image& i) { toSrgb.apply(i); }},
  };
  std::cout << fmt::format(
      "bench passes: {}x{}, moderate's settings, {} runs each (median after 1 warm-up)\n", width,
      height, frames);
  std::cout << fmt::format("{:<12} {:>10} {:>12}\n", "pass", "ms/frame", "CPU ms/frame");
  Image frame = plate;
  double wallSum = 0.0, cpuSum = 0.0;
  for (const Pass& pass : passes) {
    std::vector<double> wall, cpu;
    for (int i = 0; i <= frames; ++i) {
      const Image before = frame;
      const auto started = std::chrono::steady_clock::now();
      const double cpuStarted = processCpuMs();
      pass.run(frame);
      if (i > 0) {
        wall.push_back(1000.0 * secondsSince(started));
        cpu.push_back(processCpuMs() - cpuStarted);
      }
      if (i < frames) frame = before;  // every run sees the same input
    }
    wallSum += median(wall), cpuSum += median(cpu);
    std::cout << fmt::format("{:<12} {:>10.2f} {:>12.2f}\n", pass.name, median(wall), median(cpu));
  }
  std::cout << fmt::format("{:<12} {:>10.2f} {:>12.2f}\n", "all five", wallSum, cpuSum);
}

// ffmpeg's command with the encoder settings pluvia's movie writer uses (io/movie_writer.cpp),
// threads included, writing `output`.
std::vector<std::string> withX264(std::vector<std::string> command, const std::string& threads,
                                  const stdfs::path& output) {
  for (const char* arg :
       {"-c:v", "libx264", "-preset", "medium", "-crf", "16", "-pix_fmt", "yuv420p", "-threads"})
    command.emplace_back(arg);
  command.push_back(threads);
  command.push_back(output.string());
  return command;
}

}  // namespace

void addBenchCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand(
      "bench", "benchmark a render against ffmpeg's decode+encode of the same clip");
  struct Args {
    std::string input, preset = "moderate";
    std::vector<std::string> sets;
    int frames = 48;
    std::string strokes, size = "720x480", backend = "both", lod, saveAtlas;
    int64_t drops = 0;
    double rate = 8.0;
    bool depthPlane = false, passes = false, day = false, lookdev = false;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("INPUT", args->input, "clip to bench; default: the example scaled to 1080p");
  cmd->add_option("-p,--preset", args->preset, "preset name or path");
  cmd->add_option("--set", args->sets, "override KEY=VALUE");
  cmd->add_option("--frames", args->frames,
                  "frames to render (with --strokes: timed frames per count, default 30)")
      ->check(CLI::Range(1, 100000));
  cmd->add_option(
      "--strokes", args->strokes,
      "bench the GPU rain insertion alone: streak counts, e.g. 10000,20000,40000,80000");
  cmd->add_option("--size", args->size, "with --strokes: frame size WIDTHxHEIGHT (720x480)");
  cmd->add_option("--save-atlas", args->saveAtlas,
                  "with --strokes: also write the stroke atlas benched, as JSON, for "
                  "pluvia-bench-strokes --atlas on a machine without pluvia's image libraries");
  cmd->add_option("--lod", args->lod,
                  "bench rain.lod_px: time and rain AOV error of each size against 0 (every "
                  "drop), e.g. 0,0.5,1,1.5 at --size (default 1920x1080)");
  cmd->add_option("--rate", args->rate, "with --lod: rain rate in mm/h (8, moderate's)")
      ->check(CLI::Range(0.1, 500.0));
  cmd->add_option("--drops", args->drops,
                  "bench the drop simulation alone (CPU per frame), e.g. 100000")
      ->check(CLI::Range(int64_t(1), int64_t(10000000)));
  cmd->add_option("--backend", args->backend,
                  "with --strokes: the rain renderer to time: egl, cpu, auto (as a render "
                  "chooses) or both (egl then cpu, and their ratio; the default)")
      ->check(CLI::IsMember({"egl", "cpu", "auto", "both"}));
  cmd->add_flag("--passes", args->passes,
                "bench the per-pixel passes alone (colour in and out, darken, blur, fog) on one "
                "frame of --size (default 1920x1080)");
  cmd->add_flag("--day", args->day,
                "put the day-time stages to work (skylight fog, a sun behind the camera, the "
                "ground in view: cli/bench_day.h) and print their cost over the rain stage's");
  cmd->add_flag("--lookdev", args->lookdev,
                "bench the look-dev loop: one frame at --proxy 0.5 with a cold --cache, then after "
                "each of five look changes (--set of rate, wind, opacity, fog, darken) with the "
                "cache warm; INPUT or a 1080p PNG sequence of the bundled example");
  cmd->add_flag("--depth-plane", args->depthPlane,
                "with --strokes: give the frame a scene depth plane (3-50 m)");
  cmd->callback([=, &invocation] {
    if (args->lookdev) {
      (void)runLookdevBench(args->input, args->preset);
      return;
    }
    if (args->drops > 0) {
      runDropBench(args->drops, cmd->count("--frames") > 0 ? args->frames : 30);
      return;
    }
    if (!args->lod.empty()) {
      runLodBench(args->lod, cmd->count("--size") > 0 ? args->size : "1920x1080",
                  cmd->count("--frames") > 0 ? args->frames : 10, args->rate);
      return;
    }
    if (args->passes) {
      runPassBench(cmd->count("--size") > 0 ? args->size : "1920x1080",
                   cmd->count("--frames") > 0 ? args->frames : 20);
      return;
    }
    if (!args->strokes.empty()) {
      const bool framesGiven = cmd->count("--frames") > 0;
      const rain::StrokeLibrary library = rain::loadStrokeLibrary(rain::builtinStrokeLibraryPath());
      if (!args->saveAtlas.empty()) saveAtlasJson(library.atlas, args->saveAtlas);
      runStrokeBench(library.atlas, args->strokes, args->size, framesGiven ? args->frames : 30,
                     args->depthPlane, args->backend);
      return;
    }
    // Removed however the bench ends: an error (a missing clip, a failed encode) leaves nothing.
    const TemporaryFolder temporary("pluvia-bench");
    const stdfs::path& folder = temporary.path();
    std::string input = args->input.empty() ? makeBenchClip(folder, args->frames) : args->input;
    std::vector<std::string> sets = args->day ? dayBenchOverrides() : std::vector<std::string>{};
    sets.insert(sets.end(), args->sets.begin(), args->sets.end());
    Preset preset = loadPreset(args->preset, sets);

    // ffmpeg alone: decode and encode with the settings pluvia's movie reader and writer use,
    // threads included (io/movie_reader.cpp, io/movie_writer.cpp).
    const std::string threads = std::to_string(threadLimit());
    auto started = std::chrono::steady_clock::now();
    double cpuStarted = cpuSecondsWithChildren();
    std::vector<std::string> passthrough = {
        "ffmpeg", "-y", "-v",  "error",     "-threads",
        threads,  "-i", input, "-frames:v", std::to_string(args->frames)};
    auto r = runProcess(withX264(passthrough, threads, folder / "ffmpeg_passthrough.mp4"));
    const double ffmpegSeconds = secondsSince(started);
    const double ffmpegCpuSeconds = cpuSecondsWithChildren() - cpuStarted;
    if (r.exitCode != 0) throw Error("ffmpeg passthrough failed: " + r.output);

    // The movie rendered twice into one --cache: cold, here (a fresh cache: a shot's first render,
    // its stages timed), then warm, as a farm's chunks run after `pluvia prepare` (the whole
    // `pluvia render` command, as the EXR floor below is measured).
    const std::string cacheDir = (folder / "cache").string();
    const stdfs::path raw = folder / "pluvia_render.yuv";
    MovieRun cold;
    renderBenchMovie(cold, input, preset, args->frames, folder / "pluvia_render.mp4", raw, cacheDir,
                     invocation.commandLine);
    std::vector<std::string> warmArgs = {
        "--cache", cacheDir, "--frames",
        fmt::format("{}-{}", cold.firstFrame, *cold.request.lastFrame)};
    for (const std::string& set : sets) warmArgs.insert(warmArgs.end(), {"--set", set});
    const double warmSeconds =
        timedRender((folder / "pluvia_warm.mp4").string(), input, args->preset, warmArgs);
    StageTimes& times = cold.times;
    const RenderRequest& request = cold.request;
    const double pluviaSeconds = cold.seconds;
    const double pluviaCpuSeconds = cold.cpuSeconds;
    const int frames = cold.frames;

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
    // The encoder's own share: ffmpeg encoding the very 8-bit 4:2:0 Y'CbCr that pluvia's writer
    // piped it for H.264 (io/movie_writer.cpp), with the same settings. Rain is fine, temporally
    // incoherent detail: it costs libx264 more than the plate, and no renderer can beat this
    // rate. (The movie decoded again would not do: its crf 16 smoothing costs x264 a fifth less
    // time than the frames pluvia gave it.)
    const ClipInfo rendered = openClip(request.output.path)->info();
    started = std::chrono::steady_clock::now();
    cpuStarted = cpuSecondsWithChildren();
    std::vector<std::string> encodeOnly = {
        "ffmpeg",   "-y",
        "-v",       "error",
        "-f",       "rawvideo",
        "-pix_fmt", "yuv420p",
        "-s",       fmt::format("{}x{}", rendered.width, rendered.height),
        "-r",       fmt::format("{}", rendered.fps),
        "-i",       raw.string()};
    auto encoded = runProcess(withX264(encodeOnly, threads, folder / "ffmpeg_encode_only.mp4"));
    const double encodeSeconds = secondsSince(started);
    const double encodeCpuSeconds = cpuSecondsWithChildren() - cpuStarted;
    if (encoded.exitCode != 0) throw Error("ffmpeg could not encode the render: " + encoded.output);

    const double pluviaFps = frames / pluviaSeconds;
    const double ffmpegFps = args->frames / ffmpegSeconds;
    const double encodeFps = frames / encodeSeconds;
    std::cout << fmt::format(
        "encoder settings: libx264 -preset medium -crf 16 -pix_fmt yuv420p -threads {0} (decoder "
        "-threads {0})\n",
        threads);
    const double warmFps = frames / warmSeconds;
    std::cout << fmt::format(
        "pluvia end to end:      {:.2f} frames/s ({:.1f} s; a fresh --cache), warm {:.2f} "
        "frames/s ({:.1f} s; the per-clip setup from the cache)\n",
        pluviaFps, pluviaSeconds, warmFps, warmSeconds);
    std::cout << fmt::format("ffmpeg decode+encode:   {:.2f} frames/s ({:.1f} s; the plate)\n",
                             ffmpegFps, ffmpegSeconds);
    std::cout << fmt::format(
        "ffmpeg encode only:     {:.2f} frames/s ({:.1f} s; the yuv420p frames pluvia piped it)\n",
        encodeFps, encodeSeconds);
    std::cout << fmt::format("ratio pluvia / ffmpeg:  {:.3f}\n", pluviaFps / ffmpegFps);
    std::cout << fmt::format("ratio pluvia / encode only: {:.3f} (warm {:.3f})\n",
                             pluviaFps / encodeFps, warmFps / encodeFps);
    // On a machine shared with other jobs the wall times swing; the CPU time each run cost
    // (every thread, ffmpeg's processes included) does much less.
    std::cout << fmt::format(
        "CPU s per frame: pluvia {:.3f} (with its ffmpeg decoder and encoder), ffmpeg "
        "decode+encode {:.3f}, ffmpeg encode only {:.3f}; ratio ffmpeg / pluvia: {:.3f} (encode "
        "only / pluvia: {:.3f})\n",
        pluviaCpuSeconds / std::max(1, frames), ffmpegCpuSeconds / args->frames,
        encodeCpuSeconds / std::max(1, frames),
        (ffmpegCpuSeconds / args->frames) / (pluviaCpuSeconds / std::max(1, frames)),
        encodeCpuSeconds / pluviaCpuSeconds);
    std::cout << "(stage times overlap: decode and encode run on their own threads)\n";
    if (args->day) printDayStageRatios(times, frames);
    if (args->input.empty()) {
      std::cout << "\nthe other floors, on 1080p sequences of the example:\n";
      const ExrFloor exr = measureExrFloor(folder / "exr", args->preset);
      const TimecodeFloor timecode = measureTimecodeFloor(folder / "timecode", args->preset);
      const LookdevTimes lookdev = runLookdevBench("", args->preset);
      std::cout << fmt::format(
          "\nfloors, pluvia against each in this run (frames per second, or time for the last "
          "two):\n"
          "  movie:    pluvia / x264 alone on pluvia's output        {:6.3f}  (goal >= 0.8; "
          "warm --cache, {:.1f} s against {:.1f} s; cold {:.3f}, {:.1f} s)\n"
          "  EXR:      pluvia / oiiotool copying the {} frames       {:6.3f}  (goal >= 0.5; "
          "warm --cache, {:.1f} s against {:.1f} s; cold {:.3f}, {:.1f} s)\n"
          "  timecode: frames 86401-86404 / frames 1-4, time        {:6.3f}  (goal <= 1.5)\n"
          "  look-dev: a warm look change / the cold render, time  {:6.3f}  (warm {:.2f} s; "
          "goal <= 2 s)\n",
          warmFps / encodeFps, warmSeconds, encodeSeconds, pluviaFps / encodeFps, pluviaSeconds,
          exr.frames, exr.oiiotoolSeconds / exr.warmSeconds, exr.warmSeconds, exr.oiiotoolSeconds,
          exr.oiiotoolSeconds / exr.coldSeconds, exr.coldSeconds,
          timecode.fromTimecodeSeconds / timecode.fromOneSeconds,
          lookdev.warmSeconds / lookdev.coldSeconds, lookdev.warmSeconds);
    }
  });
}

}  // namespace pluvia::cli
