#include <iostream>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "pipeline/render_job.h"
#include "stages/registry.h"

namespace pluvia::cli {

void addPlanCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd =
      app.add_subcommand("plan", "say what a render would run and what it leaves out, and why");
  struct Args {
    std::string input, preset, cache;
    std::vector<std::string> sets;
    bool resolved = false;
  };
  auto args = std::make_shared<Args>();
  addClipPresetOptions(cmd, args->input, args->preset, args->sets);
  cmd->add_option("--cache", args->cache, "cache folder for per-clip analysis");
  cmd->add_flag("--resolved", args->resolved, "print the fully resolved preset as JSON instead");
  cmd->callback([=] {
    Preset preset = loadPreset(args->preset, args->sets);
    if (args->resolved) {
      std::cout << preset.json().dump(2) << "\n";
      return;
    }
    ClipInfo clip;
    Plan plan = planJob(args->input, preset, args->cache, allStages(), &clip);
    std::cout << fmt::format(
        "plan for {} ({}x{}, {} frames {}-{}, {} fps) with preset {} (hash {}):\n", clip.path,
        clip.width, clip.height, clip.frames.size(), clip.frames.front(), clip.frames.back(),
        clip.fps, preset.source(), preset.hash());
    std::cout << plan.text();
  });
}

}  // namespace pluvia::cli
