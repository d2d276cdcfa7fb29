// `pluvia report optics`: the table of error against run time of the drop-shading methods.
#include <iostream>

#include "commands.h"
#include "optics/environment_file.h"
#include "optics/optics_report.h"
#include "optics/test_environment.h"

namespace pluvia::cli {

void addReportCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand("report", "measurement reports");
  cmd->require_subcommand(1);
  auto* optics =
      cmd->add_subcommand("optics", "drop shading: error against the ray-traced reference vs time");
  struct Args {
    std::string env, csv, plot;
    optics::OpticsReportSettings settings;
  };
  auto args = std::make_shared<Args>();
  optics->add_option("--env", args->env,
                     "equirect HDR (default: a built-in test environment with a sun)");
  optics->add_option("--csv", args->csv, "also write the table as CSV");
  optics->add_option("--plot", args->plot, "also write error vs time as a PNG");
  optics
      ->add_option("--directions", args->settings.directions, "view directions (Fibonacci sphere)")
      ->check(CLI::Range(1, 100000));
  optics
      ->add_option("--ref-samples", args->settings.referenceSamples,
                   "rays per direction of the reference")
      ->check(CLI::Range(1, 1 << 26));
  optics->add_option("--max-terms", args->settings.maxTerms, "rows N = 1..this")
      ->check(CLI::Range(1, 50));
  optics->add_option("--max-order", args->settings.maxOrder, "rows L = 1..this")
      ->check(CLI::Range(1, 8));
  optics->callback([=, &invocation] {
    const EquirectMap env =
        args->env.empty() ? optics::builtinTestEnvironment() : optics::loadEnvironment(args->env);
    const optics::OpticsReport report = optics::runOpticsReport(env, args->settings);
    std::cout << "environment: " << (args->env.empty() ? "built-in test environment" : args->env)
              << "\n"
              << optics::formatOpticsReport(report);
    if (!args->csv.empty()) optics::writeOpticsReportCsv(report, args->csv);
    if (!args->plot.empty()) optics::writeOpticsReportPlot(report, args->plot);
    invocation.exitCode = 0;
  });
}

}  // namespace pluvia::cli
