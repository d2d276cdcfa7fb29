// `pluvia strokes`: a stroke library cut from real rain footage (Wang et al. section 2): the
// clip is derained window by window (Eq. 1) and single strokes are cut from the mattes.
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "derain/clip_derain.h"
#include "derain/stroke_extraction.h"
#include "io/clip_reader.h"
#include "rain/stroke_library.h"
#include "util/error.h"
#include "util/fs.h"
#include "util/log.h"

namespace pluvia::cli {
namespace {

// Fewer strokes than this repeat visibly: every drop draws one of the library's strokes, so a
// handful of shapes recur all over the frame.
constexpr size_t kVariedLibraryStrokes = 20;

// The library's two files, LIBRARY.json and the atlas beside it.
std::vector<std::string> libraryFiles(const std::string& library) {
  const std::filesystem::path json(library);
  return {library, (json.parent_path() / (json.stem().string() + ".png")).string()};
}

}  // namespace

void addStrokesCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand(
      "strokes", "cut a stroke library (LIBRARY.json + LIBRARY.png) from real rain footage");
  struct Args {
    std::string input, output, frames;
    derain::ClipDerainSettings clip;
    derain::StrokeExtractionSettings strokes;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("INPUT", args->input, "rain footage: movie, image sequence (rain.%05d.jpg)")
      ->required();
  cmd->add_option("-o,--output", args->output, "the library to write, LIBRARY.json (atlas beside)")
      ->required();
  cmd->add_option("--count", args->strokes.count, "strokes kept, best first")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  cmd->add_option("--frames", args->frames, "FIRST-LAST, in the clip's frame numbers")
      ->check(nonEmptyText());
  cmd->add_option("--window", args->clip.window, "frames per derain solve")
      ->check(CLI::Range(3, 1000))
      ->capture_default_str();
  cmd->add_option("--lambda", args->clip.solver.lambda, "weight of the background's smoothness")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--mu", args->clip.solver.mu, "weight of the matte's smoothness along the rain")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->callback([=, &invocation] {
    if (!args->frames.empty()) {
      std::tie(args->clip.firstFrame, args->clip.lastFrame) = parseFrameRange(args->frames);
    }
    refuseOverwritingInput(openClip(args->input)->info().files, "-o", libraryFiles(args->output));

    derain::ClipStrokes cut = derain::cutStrokesFromClip(args->input, args->clip, args->strokes);
    rain::StrokeLibrary& library = cut.library;
    const std::string& angle = cut.angleDescription;
    if (library.strokes.empty()) {
      throw Error(fmt::format("no rain strokes found in {} ({} frames, {}{}): nothing written",
                              args->input, cut.frames, angle,
                              cut.framesCut == 0 ? "; without a direction no frame was cut" : ""),
                  {"strokes", {}, args->input});
    }
    if (library.strokes.size() < kVariedLibraryStrokes)
      log::warning(fmt::format(
          "strokes: only {} stroke{} in {} ({}): a library this small repeats its shapes all "
          "over the frame. The clip shows too little rain the derain can separate{}; more "
          "frames, a clip with more visible rain, or rain.strokes builtin give varied rain",
          library.strokes.size(), library.strokes.size() == 1 ? "" : "s", args->input, angle,
          cut.framesCut < cut.frames
              ? fmt::format(" (only {} of the {} frames were cut: the others came before any "
                            "window saw the rain's direction)",
                            cut.framesCut, cut.frames)
              : std::string()));
    library.source = args->input;
    library.command = invocation.commandLine;
    rain::saveStrokeLibrary(library, args->output);
    std::cout << fmt::format(
        "strokes: kept {} of {} candidates from {} frames of {}, {}, atlas {}x{} -> {}\n",
        library.strokes.size(), cut.candidates, cut.frames, args->input, angle, library.atlas.width,
        library.atlas.height, args->output);
    invocation.exitCode = 0;
  });
}

}  // namespace pluvia::cli
