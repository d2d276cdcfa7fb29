#include <algorithm>
#include <iostream>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "pipeline/render_job.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/interrupt.h"
#include "util/log.h"
#include "util/thread_limit.h"

namespace pluvia::cli {

void addRenderCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand("render", "render rained frames from a clip");
  struct Args {
    std::string input, output, preset, frames, cache, aov;
    std::string codec = "h264", exrType = "half", exrCompression = "piz";
    std::vector<std::string> sets;
    int threads = 2;
    double proxy = 1.0;
    bool skipExisting = false, stats = false, requireCache = false;
  };
  auto args = std::make_shared<Args>();
  addClipPresetOptions(cmd, args->input, args->preset, args->sets);
  cmd->add_option("-o,--output", args->output,
                  "sequence pattern (out.####.exr/png/tif/dpx) or movie (out.mp4)")
      ->required();
  cmd->add_option("--frames", args->frames,
                  "FIRST-LAST, FIRST-LASTxSTEP or a comma list (1001-1100x2,1150), in the clip's "
                  "frame numbers");
  cmd->add_option("--threads", args->threads,
                  "threads for every pool: decoding, colour conversion, encoding (default 2)")
      ->check(CLI::Range(1, 64));
  cmd->add_option("--codec", args->codec,
                  "movie codec: h264 (default), prores_4444, prores_422hq, dnxhr_hq, dnxhr_hqx, "
                  "dnxhr_444 (ProRes and DNxHR in .mov or .mkv)");
  cmd->add_option("--exr-type", args->exrType, "EXR samples: half (default) or float")
      ->check(CLI::IsMember({"half", "float"}));
  cmd->add_option("--exr-compression", args->exrCompression,
                  "EXR compression: piz (default), zip, zips, dwaa, dwab, b44, b44a, pxr24, rle, "
                  "none");
  cmd->add_option("--cache", args->cache, "cache folder for per-clip analysis");
  cmd->add_flag("--require-cache", args->requireCache,
                "fail when per-clip analysis is missing from --cache instead of computing it "
                "(render chunks after pluvia prepare)");
  cmd->add_flag("--skip-existing", args->skipExisting,
                "leave frames that already exist (resume a job)");
  cmd->add_flag("--stats", args->stats, "print a per-stage timing summary");
  cmd->add_option("--aov", args->aov,
                  "extra outputs: rain,matte,depth,lights,splash,glare,darken,blur,fog");
  cmd->add_option("--proxy", args->proxy,
                  "render at this fraction of the plate's size, in (0, 1], for quick looks");
  cmd->callback([=, &invocation] {
    checkProxyScale(args->proxy);
    RenderRequest request;
    request.input = args->input;
    request.output = args->output;
    if (!args->frames.empty()) {
      setFrames(request, args->frames);
    }
    request.threads = args->threads;
    request.format.codec = args->codec;
    request.format.exrSampleType = args->exrType;
    request.format.exrCompression = args->exrCompression;
    request.cacheDir = args->cache;
    if (args->requireCache && args->cache.empty())
      throw UsageError("--require-cache needs --cache DIR");
    request.requireCache = args->requireCache;
    request.skipExisting = args->skipExisting;
    request.commandLine = invocation.commandLine;
    request.proxyScale = args->proxy;
    for (size_t start = 0; !args->aov.empty() && start <= args->aov.size();) {
      size_t comma = args->aov.find(',', start);
      std::string aov = args->aov.substr(start, comma - start);
      if (aov != "rain" && aov != "matte" && aov != "depth" && aov != "lights" && aov != "splash" &&
          aov != "glare" && aov != "darken" && aov != "blur" && aov != "fog") {
        throw UsageError(
            fmt::format("--aov: unknown output '{}' (known: rain, matte, depth, lights, splash, "
                        "glare, darken, blur, fog)",
                        aov));
      }
      // Named twice, written once (the second copy made unnamed channels).
      if (std::find(request.aovs.begin(), request.aovs.end(), aov) == request.aovs.end())
        request.aovs.push_back(aov);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    Preset preset = loadPresetForProxy(args->preset, args->sets, args->proxy);
    InterruptHandlers stopCleanly;
    const ThreadLimit threadCap(args->threads);
    StageTimes times;
    auto started = std::chrono::steady_clock::now();
    RenderSummary summary = renderJob(request, preset, allStages(), times);
    const double seconds = secondsSince(started);
    std::string existing;
    if (summary.framesSkipped)
      existing += fmt::format(", {} existing frames skipped", summary.framesSkipped);
    if (summary.framesRedone) {
      existing += fmt::format(
          ", {} existing frames rendered again (empty, unreadable, or not what this render writes)",
          summary.framesRedone);
    }
    log::info(fmt::format("wrote {} {}frames to {} in {:.1f} s{}", summary.framesWritten,
                          request.proxyScale != 1.0 ? "proxy " : "", request.output, seconds,
                          existing.empty() ? "" : " (" + existing.substr(2) + ")"));
    if (args->stats) std::cout << times.summary(summary.framesWritten);
  });
}

}  // namespace pluvia::cli
