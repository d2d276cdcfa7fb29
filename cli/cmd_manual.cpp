// `pluvia man` and `pluvia completion`: the man page and the bash completion script, made from
// the command line's definition (cli_manual.h).
#include <iostream>

#include "cli_manual.h"
#include "commands.h"
#include "pluvia/version.h"
#include "preset/preset.h"
#include "process_variables.h"

namespace pluvia::cli {
namespace {

const CLI::App& rootOf(const CLI::App& command) {
  const CLI::App* at = &command;
  while (at->get_parent()) at = at->get_parent();
  return *at;
}

}  // namespace

void addManualCommands(CLI::App& app, Invocation&) {
  auto* man = app.add_subcommand(
      "man", "print the man page (roff): pluvia man | man -l -, or save it as pluvia.1");
  man->callback([man] {
    const CLI::App& root = rootOf(*man);
    std::cout << manPage(root, kVersion, root.get_footer(), kProcessVariables);
  });
  auto* completion = app.add_subcommand(
      "completion", "print the bash completion script: source <(pluvia completion)");
  completion->callback(
      [completion] { std::cout << bashCompletion(rootOf(*completion), shippedPresetNames()); });
}

}  // namespace pluvia::cli
