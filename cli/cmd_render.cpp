#include <algorithm>
#include <iostream>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "pipeline/render_job.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/fs.h"
#include "util/interrupt.h"
#include "util/log.h"
#include "util/thread_limit.h"

namespace pluvia::cli {

void addRenderCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand("render", "render rained frames from a clip");
  struct Args {
    std::string input, output, preset, frames, cache;
    RenderOutputOptions writes;
    std::vector<std::string> sets;
    int threads = 2;
    bool skipExisting = false, stats = false, requireCache = false;
    std::optional<int64_t> startFrame;
  };
  auto args = std::make_shared<Args>();
  addClipPresetOptions(cmd, args->input, args->preset, args->sets);
  cmd->add_option("-o,--output", args->output,
                  "sequence pattern (out.####.exr/png/tif/dpx) or movie (out.mp4)")
      ->required();
  cmd->add_option("--frames", args->frames,
                  "FIRST-LAST, FIRST-LASTxSTEP or a comma list (1001-1100x2,1150), in the clip's "
                  "frame numbers")
      ->check(nonEmptyText());
  cmd->add_option("--threads", args->threads,
                  "threads for every pool: decoding, colour conversion, encoding (default 2)")
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--cache", args->cache, "cache folder for per-clip analysis");
  cmd->add_flag("--require-cache", args->requireCache,
                "fail when per-clip analysis is missing from --cache instead of computing it "
                "(render chunks after pluvia prepare)");
  cmd->add_flag("--skip-existing", args->skipExisting,
                "leave frames that already exist (resume a job)");
  cmd->add_flag("--stats", args->stats, "print a per-stage timing summary");
  addRenderOutputOptions(cmd, args->writes);
  addStartFrameOption(cmd, args->startFrame);
  cmd->callback([=, &invocation] {
    checkProxyScale(args->writes.proxy);
    args->writes.refuseOptionsNotFor(args->output);
    RenderRequest request;
    request.input = args->input;
    request.movieFirstFrame = args->startFrame;
    request.output = OutputTarget::classify(args->output);
    if (!args->frames.empty()) {
      setFrames(request, args->frames);
    }
    request.threads = args->threads;
    request.format.codec = args->writes.codec;
    request.format.exrSampleType = args->writes.exrType;
    request.format.exrCompression = args->writes.exrCompression;
    request.format.tiffSampleType = args->writes.tiffType;
    request.format.makeFolders =
        args->writes.makeFolders ? fs::MakeFolders::All : fs::MakeFolders::LastLevel;
    request.cacheDir = args->cache;
    if (args->requireCache && args->cache.empty())
      throw UsageError("--require-cache needs --cache DIR");
    request.requireCache = args->requireCache;
    request.skipExisting = args->skipExisting;
    request.commandLine = invocation.commandLine;
    request.proxyScale = args->writes.proxy;
    request.aovs = args->writes.aovs();
    Preset preset = loadPresetForProxy(args->preset, args->sets, args->writes.proxy);
    InterruptHandlers stopCleanly;
    const ThreadLimit threadCap(args->threads);
    log::info(fmt::format("threads: {}", threadLimit()));  // a farm chunk's log shows its share
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
                          request.proxyScale != 1.0 ? "proxy " : "", request.output.path, seconds,
                          existing.empty() ? "" : " (" + existing.substr(2) + ")"));
    if (args->stats) std::cout << times.summary(summary.framesWritten);
  });
}

}  // namespace pluvia::cli
