// pluvia prepare: the clip's per-clip analysis into the cache, once, before a farm's chunks.
#include <iostream>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "pipeline/prepare_job.h"
#include "stages/registry.h"
#include "util/interrupt.h"
#include "util/log.h"
#include "util/timer.h"

namespace pluvia::cli {

void addPrepareCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand(
      "prepare",
      "compute the per-clip analysis a render needs (lighting, COLMAP tracking, strokes) into "
      "--cache, so that render chunks only read it");
  struct Args {
    std::string input, preset, cache;
    std::vector<std::string> sets;
    double proxy = 1.0;
    std::optional<int64_t> startFrame;
  };
  auto args = std::make_shared<Args>();
  addClipPresetOptions(cmd, args->input, args->preset, args->sets);
  cmd->add_option("--cache", args->cache, "cache folder for per-clip analysis")->required();
  cmd->add_option("--proxy", args->proxy,
                  "for renders at this fraction of the plate's size, in (0, 1]");
  addStartFrameOption(cmd, args->startFrame);
  cmd->callback([=, &invocation] {
    checkProxyScale(args->proxy);
    RenderRequest request;
    request.input = args->input;
    request.movieFirstFrame = args->startFrame;
    request.cacheDir = args->cache;
    request.commandLine = invocation.commandLine;
    request.proxyScale = args->proxy;
    Preset preset = loadPresetForProxy(args->preset, args->sets, args->proxy);
    InterruptHandlers stopCleanly;
    StageTimes times;
    const auto started = std::chrono::steady_clock::now();
    const PrepareSummary summary = prepareJob(request, preset, allStages(), times);
    int computed = 0;
    for (const AnalysisEntry& entry : summary.entries) {
      std::cout << fmt::format("  {:<9} {:<8} {}\n", entry.cached ? "cached" : "added", entry.stage,
                               entry.path.string());
      computed += entry.cached ? 0 : 1;
    }
    log::info(summary.entries.empty()
                  ? fmt::format("nothing to prepare: this preset needs no per-clip analysis "
                                "of {}",
                                args->input)
                  : fmt::format("prepared {} ({} computed, {} already cached) in {:.1f} s",
                                args->cache, computed,
                                summary.entries.size() - static_cast<size_t>(computed),
                                secondsSince(started)));
  });
}

}  // namespace pluvia::cli
