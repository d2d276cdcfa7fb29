#include <iostream>
#include <optional>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "stages/registry.h"
#include "util/error.h"

namespace pluvia::cli {

void addDescribeCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand(
      "describe", "list the stages and their parameters (type, default, range, units)");
  auto stage = std::make_shared<std::string>();
  auto presetName = std::make_shared<std::string>();
  cmd->add_option("STAGE", *stage, "one stage or section (rain, fog, camera, ...)");
  cmd->add_option("-p,--preset", *presetName,
                  "also show what this preset sets, where it differs from the default "
                  "([NAME: value] at the line's end)");
  cmd->callback([=] {
    Schema schema = presetSchema();
    std::optional<Preset> preset;
    if (!presetName->empty()) preset = loadPreset(*presetName, {});
    const auto describe = [&](const SectionSpec& s) {
      const nlohmann::json* values =
          preset && preset->json().contains(s.name) ? &preset->json().at(s.name) : nullptr;
      return describeSection(s, values, *presetName);
    };
    std::vector<std::string> names;
    for (const auto& s : schema) names.push_back(s.name);
    if (stage->empty()) {
      std::cout << "Preset sections, in pipeline order after camera and color:\n\n";
      for (const auto& s : schema) std::cout << describe(s) << "\n";
      return;
    }
    for (const auto& s : schema) {
      if (s.name == *stage) {
        std::cout << describe(s);
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
