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

}  // namespace

void addPreviewCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand(
      "preview", "a contact sheet of a few frames: plate, rained, rain alone, depth");
  struct Args {
    std::string input, output, preset, frames, cache;
    std::vector<std::string> sets;
    int count = 3;
    std::optional<double> proxy;
    std::optional<int64_t> startFrame;
  };
  auto args = std::make_shared<Args>();
  addClipPresetOptions(cmd, args->input, args->preset, args->sets);
  cmd->add_option("-o,--output", args->output, "the contact sheet, SHEET.png")->required();
  cmd->add_option("--frames", args->frames,
                  "FIRST-LAST (or a stepped or comma list) to sample from, in the clip's numbers")
      ->check(nonEmptyText());
  cmd->add_option("--count", args->count, "frames on the sheet, spread evenly (default 3)");
  cmd->add_option("--proxy", args->proxy,
                  fmt::format("render at this fraction of the plate's size, in (0, 1] (default: "
                              "columns at most {} px wide)",
                              kMaxColumnWidthPx));
  cmd->add_option("--cache", args->cache, "cache folder for per-clip analysis");
  addStartFrameOption(cmd, args->startFrame);
  cmd->callback([=, &invocation] {
    if (args->count < 1)
      throw UsageError(fmt::format("--count {}: the sheet needs 1 frame or more", args->count));
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
    Preset preset = loadPresetForProxy(args->preset, args->sets, request.proxyScale);

    StageTimes times;
    RenderSession session(request, preset, allStages(), times);
    const std::vector<int64_t> frames = spreadFrames(session.frames(), args->count);
    session.prepareStages();
    const cv::Size tileSize(session.clip().width, session.clip().height);
    ContactSheet sheet(tileSize, 4, int(frames.size()));
    for (size_t row = 0; row < frames.size(); ++row) {
      FrameContext frame = session.readFrame(frames[row]);
      Image plate = frame.image;
      session.processFrame(frame);
      Image rain = rainOverBlack(frame.image, kRainGain);
      Image depth = depthPicture(frame.image);
      for (Image* tile : {&plate, &frame.image, &rain, &depth}) session.toOutput(*tile);
      sheet.place(int(row), 0, plate, fmt::format("plate {}", frames[row]));
      sheet.place(int(row), 1, frame.image, "rained");
      sheet.place(int(row), 2, rain, fmt::format("rain x{:g}", kRainGain));
      sheet.place(int(row), 3, depth, "depth");
    }
    writeSheet(args->output, sheet.image(), session.writerOptions().metadata);
    log::info(fmt::format(
        "wrote {} ({} frames at {}x{}{})", args->output, frames.size(), tileSize.width,
        tileSize.height,
        request.proxyScale != 1.0 ? fmt::format(", proxy {:g}", request.proxyScale) : ""));
  });
}

}  // namespace pluvia::cli
