// pluvia: physically based rain for real footage. The command line is thin: every subcommand
// is a file in cli/, the work is in the libraries under src/.
#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <new>

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "commands.h"
#include "common.h"
#include "image/color.h"
#include "io/oiio_debug.h"
#include "pluvia/version.h"
#include "preset/param_table.h"
#include "preset/preset.h"
#include "process_memory.h"
#include "process_variables.h"
#include "util/error.h"
#include "util/interrupt.h"
#include "util/log.h"
#include "util/printable.h"

namespace {
constexpr const char* kExitCodes =
    "Exit codes: 0 success, 1 error (bad input file, invalid preset, failed write), 2 usage error "
    "(bad command line), 3 farm status: the failed tasks only ran out of time, 130 and 143 a "
    "render stopped by SIGINT and SIGTERM.";
}

int main(int argc, char** argv) {
  using namespace pluvia;
  // Past a file size limit (ulimit -f) a write fails with EFBIG and pluvia reports it, instead
  // of being killed by SIGXFSZ with the file half written.
  std::signal(SIGXFSZ, SIG_IGN);
  // Output piped into a reader that stops early (`pluvia render ... 2>&1 | head`): the writes
  // fail and the command goes on to its end, which releases its lock, instead of dying with it
  // held.
  std::signal(SIGPIPE, SIG_IGN);
  keepFreedBlocksForTheNextFrame();
  CLI::App app{"pluvia: adds physically based rain to real footage.", "pluvia"};
  app.footer(kExitCodes);
  app.set_version_flag("--version", std::string("pluvia ") + kVersion + " (OpenColorIO " +
                                        colorLibraryVersion() + ")");
  app.require_subcommand(1);
  // -q, -v and --log belong to the program, and may stand anywhere on the line: before the
  // command or among its options (a farm template appends them at the end).
  app.fallthrough();
  bool quiet = false, verbose = false;
  std::string logFile;
  app.add_flag("-q,--quiet", quiet, "only warnings and errors");
  app.add_flag("-v,--verbose", verbose, "debug messages too");
  app.add_option("--log", logFile, "append every message and progress line to FILE too")
      ->type_name("FILE");

  cli::Invocation invocation;
  invocation.commandLine = cli::joinCommandLine(argc, argv);
  cli::addRenderCommand(app, invocation);
  cli::addPrepareCommand(app, invocation);
  cli::addFarmCommand(app, invocation);
  cli::addPreviewCommand(app, invocation);
  cli::addPlanCommand(app, invocation);
  cli::addValidateCommand(app, invocation);
  cli::addPresetsCommand(app, invocation);
  cli::addDescribeCommand(app, invocation);
  cli::addBenchCommand(app, invocation);
  cli::addShadeDropCommand(app, invocation);
  cli::addReportCommand(app, invocation);
  cli::addDerainCommand(app, invocation);
  cli::addStrokesCommand(app, invocation);
  cli::addMatchCommand(app, invocation);
  cli::addEnvmapCommand(app, invocation);
  cli::addDepthCommand(app, invocation);
  cli::addManualCommands(app, invocation);
  app.parse_complete_callback([&] {
    log::setLevel(quiet ? log::Level::Warning : verbose ? log::Level::Debug : log::Level::Info);
    showOiioDebugMessages(verbose);
    if (!logFile.empty()) log::setFile(logFile);
    cli::protectNamedInputs(app);
  });

  // CLI11 would only say "a subcommand is required" for a mistyped command: name it.
  for (int i = 1; i < argc; ++i) {
    std::string word = argv[i];
    if (word == "--log") ++i;  // its FILE is not a command
    if (word.rfind('-', 0) == 0) continue;
    std::vector<std::string> names;
    for (const auto* sub : app.get_subcommands({})) names.push_back(sub->get_name());
    if (std::find(names.begin(), names.end(), word) == names.end()) {
      std::string nearest = nearestWord(word, names);
      std::string commands;
      for (const auto& name : names) commands += (commands.empty() ? "" : ", ") + name;
      log::error("unknown command '" + word + "'" +
                 (nearest.empty() ? "" : ", did you mean '" + nearest + "'?") +
                 " (commands: " + commands + "; see pluvia --help)");
      return 2;
    }
    break;
  }

  try {
    applyProcessVariables();
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // CLI11 echoes the word it refused: shown escaped, so that an escape sequence in it does
    // not drive the terminal.
    std::cerr << printable(e.what(), /*keepLines=*/true)
              << "\nRun with --help for more information.\n";
    return 2;
  } catch (const UsageError& e) {
    log::error(e.describe());
    return 2;
  } catch (const PresetError& e) {
    log::error(e.describe());
    return e.isCommandLine() ? 2 : 1;
  } catch (const Error& e) {
    log::error(e.describe());
    // Whatever failed after a SIGINT or SIGTERM (ffmpeg got it too and stopped) failed for it.
    if (const int signal = interruptSignal()) return 128 + signal;
    return 1;
  } catch (const std::bad_alloc&) {
    log::error(
        "out of memory: this command needed more memory than the process may use (the "
        "machine's, ulimit -v or the job's memory limit); a smaller --proxy, fewer "
        "--threads or rain.max_drops lower it");
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    // The path and the system's reason, not the library's "filesystem error: status: ...".
    log::error(fmt::format("{}{}: {}", e.path1().string(),
                           e.path2().empty() ? "" : " -> " + e.path2().string(),
                           e.code().message()));
    return 1;
  } catch (const std::exception& e) {
    log::error(e.what());
    return 1;
  }
  // The command did its work but the log it was asked to keep is incomplete: a farm must know.
  if (log::fileFailed() && invocation.exitCode == 0) {
    log::error("the log file could not be written to the end (see the warning above)");
    return 1;
  }
  return invocation.exitCode;
}
