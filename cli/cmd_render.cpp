#include <iostream>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "pipeline/render_job.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/interrupt.h"
#include "util/log.h"

namespace pluvia::cli {

void addRenderCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand("render", "render rained frames from a clip");
  struct Args {
    std::string input, output, preset, frames, cache, aov;
    std::vector<std::string> sets;
    int threads = 2;
    double proxy = 1.0;
    bool skipExisting = false, stats = false;
  };
  auto args = std::make_shared<Args>();
  addClipPresetOptions(cmd, args->input, args->preset, args->sets);
  cmd->add_option("-o,--output", args->output,
                  "sequence pattern (out.####.exr/png/tif/dpx) or movie (out.mp4)")
      ->required();
  cmd->add_option("--frames", args->frames, "FIRST-LAST, in the clip's frame numbers");
  cmd->add_option("--threads", args->threads, "writer threads")->check(CLI::Range(1, 64));
  cmd->add_option("--cache", args->cache, "cache folder for per-clip analysis");
  cmd->add_flag("--skip-existing", args->skipExisting,
                "leave frames that already exist (resume a job)");
  cmd->add_flag("--stats", args->stats, "print a per-stage timing summary");
  cmd->add_option("--aov", args->aov, "extra outputs: rain,matte,depth,splash");
  cmd->add_option("--proxy", args->proxy,
                  "render at this fraction of the plate's size, in (0, 1], for quick looks");
  cmd->callback([=, &invocation] {
    checkProxyScale(args->proxy);
    RenderRequest request;
    request.input = args->input;
    request.output = args->output;
    if (!args->frames.empty()) {
      auto [first, last] = parseFrameRange(args->frames);
      request.firstFrame = first;
      request.lastFrame = last;
    }
    request.threads = args->threads;
    request.cacheDir = args->cache;
    request.skipExisting = args->skipExisting;
    request.commandLine = invocation.commandLine;
    request.proxyScale = args->proxy;
    for (size_t start = 0; !args->aov.empty() && start <= args->aov.size();) {
      size_t comma = args->aov.find(',', start);
      std::string aov = args->aov.substr(start, comma - start);
      if (aov != "rain" && aov != "matte" && aov != "depth" && aov != "splash") {
        throw UsageError(
            fmt::format("--aov: unknown output '{}' (known: rain, matte, depth, splash)", aov));
      }
      request.aovs.push_back(aov);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    Preset preset = loadPresetForProxy(args->preset, args->sets, args->proxy);
    InterruptHandlers stopCleanly;
    StageTimes times;
    auto started = std::chrono::steady_clock::now();
    RenderSummary summary = renderJob(request, preset, allStages(), times);
    const double seconds = secondsSince(started);
    std::string existing;
    if (summary.framesSkipped)
      existing += fmt::format(", {} existing frames skipped", summary.framesSkipped);
    if (summary.framesRedone) {
      existing += fmt::format(
          ", {} existing frames rendered again (empty, unreadable or of another preset)",
          summary.framesRedone);
    }
    log::info(fmt::format("wrote {} {}frames to {} in {:.1f} s{}", summary.framesWritten,
                          request.proxyScale != 1.0 ? "proxy " : "", request.output, seconds,
                          existing.empty() ? "" : " (" + existing.substr(2) + ")"));
    if (args->stats) std::cout << times.summary(summary.framesWritten);
  });
}

}  // namespace pluvia::cli
