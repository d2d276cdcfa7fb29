// `pluvia preview`: a contact sheet for look development. A few frames of the clip, one row
// each: the plate, the rained frame, the rain layer alone and the depth. The frames are rendered
// by the render's own session (same stages, preset resolution, --set and per-frame simulation),
// so a row shows what `pluvia render` gives for that frame at the same --proxy.
#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "image/contact_sheet.h"
#include "io/image_file_writer.h"
#include "io/sequence_pattern.h"
#include "pipeline/render_job.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/log.h"

namespace pluvia::cli {
namespace {

// Without --proxy, the sheet's columns are at most this wide.
constexpr int kMaxColumnWidthPx = 480;
// The rain layer is faint over black (streaks cover a pixel for a fraction of the exposure):
// this gain makes it visible. It is stated in the column's label.
constexpr float kRainGain = 4.0f;

// `count` frames spread evenly over `frames` (the first and the last among them); the middle
// one for a count of 1. Never more frames than there are.
std::vector<int64_t> spreadFrames(const std::vector<int64_t>& frames, int count) {
  const size_t n = std::min(frames.size(), size_t(count));
  if (n == 1) return {frames[(frames.size() - 1) / 2]};
  std::vector<int64_t> picked;
  for (size_t i = 0; i < n; ++i)
    picked.push_back(frames[(i * (frames.size() - 1) + (n - 1) / 2) / (n - 1)]);
  return picked;
}

// Writes the sheet's RGB as an 8-bit PNG (temporary file, then rename), with the render's
// metadata (`pluvia:proxy` among it on a proxy).
void writeSheet(const std::string& path, const Image& sheet,
                const std::map<std::string, std::string>& metadata) {
  std::vector<OutputChannel> channels;
  for (int c = 0; c < 3; ++c)
    channels.push_back({std::string(1, "RGB"[c]), sheet.rgba.data() + c, 4});
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  if (!folder.empty()) std::filesystem::create_directories(folder);
  writeImageFile(path, sheet.width, sheet.height, channels, metadata, std::nullopt);
}

// A preset's name on the sheet: a shipped name as given, a preset file by its stem.
std::string presetLabel(const std::string& nameOrPath) {
  return std::filesystem::path(nameOrPath).stem().string();
}

}  // namespace

void addPreviewCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand(
      "preview",
      "a contact sheet of a few frames (or one frame under several presets): plate, rained, rain "
      "alone, depth");
  struct Args {
    std::string input, output, preset, frames, cache;
    std::vector<std::string> sets, presets;
    int count = 3;
    std::optional<double> proxy;
    std::optional<int64_t> startFrame;
  };
  auto args = std::make_shared<Args>();
  addClipPresetOptions(cmd, args->input, args->preset, args->sets);
  // -p or --presets: one of the two (checked in the callback, naming both).
  CLI::Option* presetOption = cmd->get_option("-p")->required(false);
  cmd->add_option("--presets", args->presets,
                  "compare presets instead of -p: a row per preset (NAME,NAME,... or paths), "
                  "each at the same frames (--count 1 unless given), --set applied to each")
      ->delimiter(',')
      ->excludes(presetOption);
  cmd->add_option("-o,--output", args->output, "the contact sheet, SHEET.png")->required();
  cmd->add_option("--frames", args->frames,
                  "FIRST-LAST (or a stepped or comma list) to sample from, in the clip's numbers")
      ->check(nonEmptyText());
  CLI::Option* countOption = cmd->add_option(
      "--count", args->count, "frames on the sheet, spread evenly (default 3; 1 with --presets)");
  cmd->add_option("--proxy", args->proxy,
                  fmt::format("render at this fraction of the plate's size, in (0, 1] (default: "
                              "columns at most {} px wide)",
                              kMaxColumnWidthPx));
  cmd->add_option("--cache", args->cache, "cache folder for per-clip analysis");
  addStartFrameOption(cmd, args->startFrame);
  cmd->callback([=, &invocation] {
    if (args->preset.empty() && args->presets.empty())
      throw UsageError("give -p PRESET, or --presets NAME,NAME,... for a row per preset");
    const bool comparing = !args->presets.empty();
    const int count = comparing && countOption->count() == 0 ? 1 : args->count;
    if (count < 1)
      throw UsageError(fmt::format("--count {}: the sheet needs 1 frame or more", count));
    if (args->proxy) checkProxyScale(*args->proxy);
    if (lowerExtension(args->output) != "png")
      throw UsageError(fmt::format("-o {}: the contact sheet is a PNG (SHEET.png)", args->output));
    RenderRequest request;
    request.input = args->input;
    request.movieFirstFrame = args->startFrame;
    request.output = OutputTarget::classify(
        args->output);  // refused when it names an input file; sets the colour-out
    if (!args->frames.empty()) {
      setFrames(request, args->frames);
    }
    request.cacheDir = args->cache;
    request.aovs = {"rain"};
    request.commandLine = invocation.commandLine;
    if (args->proxy) {
      request.proxyScale = *args->proxy;
    } else {
      const int plateWidth = openClip(args->input)->info().width;
      request.proxyScale = std::min(1.0, double(kMaxColumnWidthPx) / plateWidth);
    }
    const std::vector<std::string> presetNames =
        comparing ? args->presets : std::vector<std::string>{args->preset};
    // Every preset resolved before any frame is rendered: a mistake in the third is said at once.
    std::vector<Preset> presets;
    for (const std::string& name : presetNames)
      presets.push_back(loadPresetForProxy(name, args->sets, request.proxyScale));

    std::optional<ContactSheet> sheet;
    std::map<std::string, std::string> metadata;
    cv::Size tileSize;
    size_t rows = 0;
    for (size_t p = 0; p < presets.size(); ++p) {
      StageTimes times;
      RenderSession session(request, presets[p], allStages(), times);
      const std::vector<int64_t> frames = spreadFrames(session.frames(), count);
      session.prepareStages();
      if (!sheet) {
        tileSize = cv::Size(session.clip().width, session.clip().height);
        sheet.emplace(tileSize, 4, int(frames.size() * presets.size()));
        metadata = session.writerOptions().metadata;
      }
      for (int64_t frameNumber : frames) {
        FrameContext frame = session.readFrame(frameNumber);
        Image plate = frame.image;
        session.processFrame(frame);
        Image rain = rainOverBlack(frame.image, kRainGain);
        Image depth = depthPicture(frame.image);
        for (Image* tile : {&plate, &frame.image, &rain, &depth}) session.toOutput(*tile);
        const int row = int(rows++);
        sheet->place(row, 0, plate, fmt::format("plate {}", frameNumber));
        sheet->place(row, 1, frame.image,
                     comparing ? presetLabel(presetNames[p]) : std::string("rained"));
        sheet->place(row, 2, rain, fmt::format("rain x{:g}", kRainGain));
        sheet->place(row, 3, depth, "depth");
      }
    }
    writeSheet(args->output, sheet->image(), metadata);
    log::info(fmt::format(
        "wrote {} ({} rows at {}x{}{})", args->output, rows, tileSize.width, tileSize.height,
        request.proxyScale != 1.0 ? fmt::format(", proxy {:g}", request.proxyScale) : ""));
  });
}

}  // namespace pluvia::cli
