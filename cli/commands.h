#pragma once
// One function per subcommand: registers its options on `app` and its action, which sets
// `exitCode`. Actions throw pluvia::Error / UsageError; main() turns them into exit codes.
#include <cstdint>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace pluvia {
struct ClipInfo;
struct SequencePattern;
class Preset;
}  // namespace pluvia

namespace pluvia::cli {

struct Invocation {
  std::string commandLine;
  int exitCode = 0;
};

void addRenderCommand(CLI::App& app, Invocation& invocation);
void addPrepareCommand(CLI::App& app, Invocation& invocation);
void addFarmCommand(CLI::App& app, Invocation& invocation);
void addPreviewCommand(CLI::App& app, Invocation& invocation);
void addPlanCommand(CLI::App& app, Invocation& invocation);
void addValidateCommand(CLI::App& app, Invocation& invocation);
void addDescribeCommand(CLI::App& app, Invocation& invocation);
void addBenchCommand(CLI::App& app, Invocation& invocation);
void addShadeDropCommand(CLI::App& app, Invocation& invocation);
void addReportCommand(CLI::App& app, Invocation& invocation);
void addDerainCommand(CLI::App& app, Invocation& invocation);
void addStrokesCommand(CLI::App& app, Invocation& invocation);
void addMatchCommand(CLI::App& app, Invocation& invocation);
void addEnvmapCommand(CLI::App& app, Invocation& invocation);
void addDepthCommand(CLI::App& app, Invocation& invocation);
void addPresetsCommand(CLI::App& app, Invocation& invocation);
void addManualCommands(CLI::App& app, Invocation& invocation);

}  // namespace pluvia::cli
