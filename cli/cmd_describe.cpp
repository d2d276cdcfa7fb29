#include <iostream>

#include <fmt/format.h>

#include "commands.h"
#include "stages/registry.h"
#include "util/error.h"

namespace pluvia::cli {

void addDescribeCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand(
      "describe", "list the stages and their parameters (type, default, range, units)");
  auto stage = std::make_shared<std::string>();
  cmd->add_option("STAGE", *stage, "one stage or section (rain, fog, camera, ...)");
  cmd->callback([=] {
    Schema schema = presetSchema();
    std::vector<std::string> names;
    for (const auto& s : schema) names.push_back(s.name);
    if (stage->empty()) {
      std::cout << "Preset sections, in pipeline order after camera and color:\n\n";
      for (const auto& s : schema) std::cout << describeSection(s) << "\n";
      return;
    }
    for (const auto& s : schema) {
      if (s.name == *stage) {
        std::cout << describeSection(s);
        return;
      }
    }
    std::string nearest = nearestWord(*stage, names);
    throw UsageError(
        fmt::format("no stage named '{}'{} (stages: {})", *stage,
                    nearest.empty() ? "" : fmt::format(", did you mean '{}'?", nearest),
                    fmt::join(names, ", ")));
  });
}

}  // namespace pluvia::cli
