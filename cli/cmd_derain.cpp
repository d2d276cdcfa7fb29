#include <optional>
// `pluvia derain`: the clean background and per-frame rain mattes of real rain footage
// (Wang et al. Eq. 1), written as sequences, with a JSON report of the solve.
#include <iostream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "common.h"
#include "derain/clip_derain.h"
#include "image/color.h"
#include "io/clip_reader.h"
#include "io/clip_writer.h"
#include "io/output_lock.h"
#include "io/output_target.h"
#include "pluvia/version.h"
#include "util/error.h"
#include "util/fs.h"
#include "util/interrupt.h"
#include "util/log.h"

namespace pluvia::cli {
namespace {

// Every path a writer would produce for the frames.
std::vector<std::string> outputPaths(const ClipWriter& writer, const std::vector<int64_t>& frames) {
  std::vector<std::string> paths;
  for (int64_t f : frames) paths.push_back(writer.pathFor(f));
  return paths;
}

nlohmann::json reportJson(const derain::ClipDerainSummary& summary,
                          const derain::ClipDerainSettings& settings, const std::string& input) {
  nlohmann::json windows = nlohmann::json::array();
  for (const auto& w : summary.windows) {
    nlohmann::json history = nlohmann::json::array();
    for (const auto& h : w.history)
      history.push_back({{"iteration", h.iteration},
                         {"objective", h.objective},
                         {"data_rms", h.dataRms},
                         {"angle_deg", h.angleDeg},
                         {"seconds", h.seconds},
                         {"cg_iterations_alpha", h.cgIterationsAlpha},
                         {"cg_iterations_background", h.cgIterationsS}});
    windows.push_back({{"first_frame", w.firstFrame},
                       {"last_frame", w.lastFrame},
                       {"registration_shift_px", w.maxShiftPx},
                       {"registration", w.registration},
                       {"registration_residual_identity", w.identityResidual},
                       {"registration_residual_motion", w.motionResidual},
                       {"angle_deg", w.angleDeg},
                       {"angle_found", w.angleFound},
                       {"iterations", w.iterations},
                       {"residual", w.residual},
                       {"noise_sigma", w.noiseSigma},
                       {"history", history}});
  }
  return {{"input", input},
          {"pluvia_version", kVersion},
          {"angle_deg", summary.angleDeg},
          {"windows_with_angle", summary.windowsWithAngle},
          {"rain_color", {summary.rainColor[0], summary.rainColor[1], summary.rainColor[2]}},
          {"iterations", summary.iterations},
          {"residual", summary.residual},
          {"seconds", summary.seconds},
          {"settings",
           {{"lambda", settings.solver.lambda},
            {"mu", settings.solver.mu},
            {"window", settings.window},
            {"max_iterations", settings.solver.maxIterations},
            {"registration", settings.registration}}},
          {"windows", windows}};
}

}  // namespace

void addDerainCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand(
      "derain", "clean background and rain mattes of rain footage (Wang et al. Eq. 1)");
  struct Args {
    std::string input, clean, matte, frames, report, mode = "background";
    derain::ClipDerainSettings settings;
    bool noRegister = false;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("INPUT", args->input,
                  "rain footage: movie, image sequence (rain.%05d.jpg) or images")
      ->required();
  cmd->add_option("-o,--output", args->clean,
                  "clean plate, a sequence pattern (clean.####.png/exr)")
      ->required();
  cmd->add_option("--matte-out", args->matte,
                  "rain mattes alpha, a sequence pattern (matte.####.png/exr)");
  cmd->add_option("--frames", args->frames, "FIRST-LAST, in the clip's frame numbers")
      ->check(nonEmptyText());
  cmd->add_option("--window", args->settings.window, "frames per solve (at least 3)")
      ->check(CLI::Range(3, 1000));
  cmd->add_option("--report", args->report, "write a JSON report of the solve");
  cmd->add_option("--lambda", args->settings.solver.lambda,
                  "weight of the background's smoothness (Eq. 1)");
  cmd->add_option("--mu", args->settings.solver.mu,
                  "weight of the mattes' smoothness along the rain (Eq. 1)");
  cmd->add_option("--iterations", args->settings.solver.maxIterations,
                  "most alternating-minimisation iterations")
      ->check(CLI::Range(0, 1000));
  cmd->add_option("--clean", args->mode,
                  "background: the solved static background S; unblend: each frame with its rain "
                  "removed, (I - alpha C) / (1 - alpha), which keeps moving objects")
      ->check(CLI::IsMember({"background", "unblend"}));
  cmd->add_flag("--no-register", args->noRegister,
                "the camera is locked off: skip frame registration");
  cmd->callback([=, &invocation] {
    derain::ClipDerainSettings settings = args->settings;
    settings.registration = !args->noRegister;
    if (!args->frames.empty())
      std::tie(settings.firstFrame, settings.lastFrame) = parseFrameRange(args->frames);
    if (!args->matte.empty() && args->matte == args->clean)
      throw UsageError("--matte-out and -o name the same files");

    InterruptHandlers stopCleanly;
    const ClipInfo clip = openClip(args->input)->info();
    std::vector<int64_t> frames;
    for (int64_t f : clip.frames)
      if (f >= settings.firstFrame && f <= settings.lastFrame) frames.push_back(f);
    WriterOptions options;
    options.fps = clip.fps;
    options.metadata = {{"pluvia:version", kVersion},
                        {"pluvia:commandLine", invocation.commandLine}};
    const OutputTarget cleanOutput = OutputTarget::classify(args->clean);
    auto cleanWriter = openClipWriter(cleanOutput, clip.width, clip.height, options);
    if (cleanWriter->isMovie())
      throw UsageError(fmt::format("-o {}: write a sequence pattern, not a movie", args->clean));
    refuseOverwritingInput(clip.files, "-o", outputPaths(*cleanWriter, frames));
    if (!args->report.empty()) refuseOverwritingInput(clip.files, "--report", {args->report});
    // Held to the end, as a render holds its output; the temporaries a killed derain left go.
    std::optional<OutputLock> cleanLock, matteLock;
    if (!frames.empty()) {
      cleanLock.emplace(cleanOutput, frames.front(), frames.back());
      cleanLock->removeStaleTemporaries();
    }
    std::unique_ptr<ClipWriter> matteWriter;
    if (!args->matte.empty()) {
      const OutputTarget matteOutput = OutputTarget::classify(args->matte);
      matteWriter = openClipWriter(matteOutput, clip.width, clip.height, options);
      if (matteWriter->isMovie())
        throw UsageError(fmt::format("--matte-out {}: write a sequence pattern", args->matte));
      refuseOverwritingInput(clip.files, "--matte-out", outputPaths(*matteWriter, frames));
      if (!frames.empty()) {
        matteLock.emplace(matteOutput, frames.front(), frames.back());
        matteLock->removeStaleTemporaries();
      }
    }
    // The solver keeps the file's encoding; convert only where the output's differs.
    const bool inputLinear = clip.isFloat, outputLinear = outputIsLinear(args->clean);
    std::unique_ptr<ColorConverter> convert;
    if (inputLinear != outputLinear)
      convert = std::make_unique<ColorConverter>(inputLinear ? "linear-rec709" : "sRGB",
                                                 outputLinear ? "linear-rec709" : "sRGB");

    const bool unblend = args->mode == "unblend";
    const derain::ClipDerainSummary summary =
        derain::derainClip(args->input, settings, [&](const derain::ClipDerainFrame& f) {
          cv::Mat clean = f.clean;
          if (unblend) {
            // Inverting the blend amplifies noise by 1 / (1 - alpha): stop short of opaque rain.
            clean = f.original.clone();
            for (int y = 0; y < clean.rows; ++y)
              for (int x = 0; x < clean.cols; ++x) {
                const float a = std::min(f.matte.at<float>(y, x), 0.9f);
                cv::Vec3f& p = clean.at<cv::Vec3f>(y, x);
                p = (p - a * f.rainColor) / (1.0f - a);
              }
          }
          Image image = imageFromMat(clean);
          if (convert) convert->apply(image);
          cleanWriter->write(f.frame, image);
          if (matteWriter) matteWriter->write(f.frame, imageFromMat(f.matte));
        });
    cleanWriter->close();
    if (matteWriter) matteWriter->close();
    if (!args->report.empty())
      fs::writeTextFile(args->report, reportJson(summary, settings, args->input).dump(2) + "\n");
    log::info(fmt::format("derain: {} frames, {}, colour ({:.3f}, {:.3f}, {:.3f}), {:.1f} s",
                          frames.size(), derain::describeRainAngle(summary), summary.rainColor[0],
                          summary.rainColor[1], summary.rainColor[2], summary.seconds));
    invocation.exitCode = 0;
  });
}

}  // namespace pluvia::cli
