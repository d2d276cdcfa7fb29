#include <iostream>

#include "commands.h"
#include "common.h"
#include "stages/registry.h"
#include "util/error.h"
#include "util/printable.h"

namespace pluvia::cli {

void addValidateCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand("validate", "check a preset and report every problem at once");
  auto preset = std::make_shared<std::string>();
  auto sets = std::make_shared<std::vector<std::string>>();
  cmd->add_option("PRESET", *preset, "preset name or path")->required();
  cmd->add_option("--set", *sets, "override KEY=VALUE (dotted key path)");
  cmd->callback([=, &invocation] {
    try {
      Preset p = loadPreset(*preset, *sets);
      // Each stage reads its settings, and checks them across keys, as a render does.
      for (const StageInfo& stage : allStages()) stage.create(p);
      std::cout << printable(p.source()) << ": valid (hash " << p.hash() << ")\n";
    } catch (const PresetError& e) {
      std::cout << printable(e.what(), /*keepLines=*/true) << "\n";
      invocation.exitCode = e.isCommandLine() ? 2 : 1;
    } catch (const Error& e) {
      std::cout << printable(*preset) << ": " << printable(e.describe(), /*keepLines=*/true)
                << "\n";
      invocation.exitCode = 1;
    }
  });
}

}  // namespace pluvia::cli
