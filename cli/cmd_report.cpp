// `pluvia report optics`: the table of error against run time of the drop-shading methods.
// `pluvia report derain`: rain extraction against synthetic ground truth and on real footage.
// `pluvia report envmap`: environments stitched from a pan against the full HDR.
// `pluvia report depth`: SfM poses and depth against a synthetic scene's truth, and real photos.
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "lab/derain_report.h"
#include "lab/envmap_report.h"
#include "lab/optics_report.h"
#include "lab/report_depth.h"
#include "lab/test_environment.h"
#include "optics/environment_file.h"
#include "util/error.h"
#include "util/log.h"

namespace pluvia::cli {

namespace {

// The folder of shared test data: --data, else $PLUVIA_SHARED_DATA, else ../shared/data beside
// the binary's install prefix or the current directory (findBesideInstall); empty when none is
// there (the reports then skip what needs it).
std::string sharedDataFolder(const std::string& option) {
  if (!option.empty()) {
    if (!std::filesystem::is_directory(option))
      throw UsageError("--data: no such folder: " + option);
    return option;
  }
  if (const char* env = std::getenv("PLUVIA_SHARED_DATA"); env && *env) return env;
  return findBesideInstall("../shared/data");
}

void addReportDerain(CLI::App& report, Invocation& invocation) {
  auto* derain = report.add_subcommand(
      "derain", "rain extraction: error vs time against synthetic truth, and on real footage");
  struct Args {
    std::string csv, plot, images, data;
    lab::DerainReportSettings settings;
  };
  auto args = std::make_shared<Args>();
  derain->add_option("--csv", args->csv, "also write the table as CSV");
  derain->add_option("--plot", args->plot, "also write PSNR vs time as a PNG");
  derain->add_option("--images", args->images,
                     "write previews here (PNG): clean plates, mattes x4, input frames");
  derain->add_option("--data", args->data,
                     "shared data folder (default: $PLUVIA_SHARED_DATA, else ../shared/data "
                     "beside the install prefix or the current directory); without it only the "
                     "example plate is used");
  derain->add_flag("--quick", args->settings.quick,
                   "one 320x240 case, short sweeps, no real footage (for tests)");
  derain->callback([=, &invocation] {
    lab::DerainReportSettings settings = args->settings;
    settings.examplePlate = findBesideInstall("examples/street/street_plate.mp4");
    settings.sharedData = sharedDataFolder(args->data);
    settings.imagesDir = args->images;
    const lab::DerainReport result = lab::runDerainReport(settings);
    std::cout << lab::formatDerainReport(result);
    if (!args->csv.empty()) lab::writeDerainReportCsv(result, args->csv);
    if (!args->plot.empty()) lab::writeDerainReportPlot(result, args->plot);
    invocation.exitCode = 0;
  });
}

void addReportEnvmap(CLI::App& report, Invocation& invocation) {
  auto* envmap = report.add_subcommand(
      "envmap", "environments stitched from a pan: SH and drop colour error vs frames and time");
  struct Args {
    std::string env, csv, plot, images, data;
    lab::EnvmapReportSettings settings;
  };
  auto args = std::make_shared<Args>();
  envmap->add_option("--env", args->env,
                     "equirect HDR (default: every HDR in the shared data's hdr/, else a "
                     "built-in test environment with a sun)");
  envmap->add_option("--csv", args->csv, "also write the table as CSV");
  envmap->add_option("--plot", args->plot, "also write drop colour error vs time as a PNG");
  envmap->add_option("--images", args->images,
                     "write panoramas here (PNG; the real photos' also as EXR)");
  envmap->add_option("--data", args->data,
                     "shared data folder (default: $PLUVIA_SHARED_DATA, else ../shared/data "
                     "beside the install prefix or the current directory); without it only the "
                     "built-in environment is used");
  envmap->add_flag("--quick", args->settings.quick,
                   "the built-in environment, 640x360 frames, 3 and 12 frames, no photos (for "
                   "tests)");
  envmap->callback([=, &invocation] {
    lab::EnvmapReportSettings settings = args->settings;
    if (!args->env.empty() && !std::filesystem::is_regular_file(args->env))
      throw UsageError("--env: no such file: " + args->env);
    settings.environment = args->env;
    settings.sharedData = sharedDataFolder(args->data);
    settings.imagesDir = args->images;
    const lab::EnvmapReport result = lab::runEnvmapReport(settings);
    std::cout << lab::formatEnvmapReport(result);
    if (!args->csv.empty()) lab::writeEnvmapReportCsv(result, args->csv);
    if (!args->plot.empty()) lab::writeEnvmapReportPlot(result, args->plot);
    invocation.exitCode = 0;
  });
}

void addReportDepth(CLI::App& report, Invocation& invocation) {
  auto* depth = report.add_subcommand(
      "depth", "camera tracking and depth (COLMAP): pose and depth error vs frames, size, time");
  struct Args {
    std::string csv, plot, images, data, workspace;
    lab::DepthReportSettings settings;
  };
  auto args = std::make_shared<Args>();
  depth->add_option("--csv", args->csv, "also write the table as CSV");
  depth->add_option("--plot", args->plot, "also write rotation and depth error vs time as a PNG");
  depth->add_option("--images", args->images,
                    "write depth vs truth previews here (PNG, the middle frame of each row)");
  depth->add_option("--data", args->data,
                    "shared data folder (default: $PLUVIA_SHARED_DATA, else ../shared/data "
                    "beside the install prefix or the current directory); without it the real "
                    "photos are skipped");
  depth->add_option("--workspace", args->workspace,
                    "keep COLMAP's folders (frames, database, models, colmap.log) here, one per "
                    "row (default: a temporary folder, removed unless COLMAP failed)");
  depth->add_flag(
      "--quick", args->settings.quick,
      "one row: every 4th of the 48 frames (13) at 1280x720, no real photos (for tests)");
  depth->callback([=, &invocation] {
    lab::DepthReportSettings settings = args->settings;
    settings.sharedData = sharedDataFolder(args->data);
    settings.imagesDir = args->images;
    settings.workspace = args->workspace;
    const lab::DepthReport result = lab::runDepthReport(settings);
    std::cout << lab::formatDepthReport(result);
    if (!args->csv.empty()) lab::writeDepthReportCsv(result, args->csv);
    if (!args->plot.empty()) lab::writeDepthReportPlot(result, args->plot);
    // The table is printed either way; a row that failed makes the command fail.
    int failed = result.real.status == "failed" ? 1 : 0;
    for (const lab::DepthReportRow& row : result.rows) failed += row.status == "failed" ? 1 : 0;
    if (failed > 0) log::error(fmt::format("report depth: {} of its rows failed", failed));
    invocation.exitCode = failed > 0 ? 1 : 0;
  });
}
}  // namespace

void addReportCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand("report", "measurement reports");
  cmd->require_subcommand(1);
  auto* optics =
      cmd->add_subcommand("optics", "drop shading: error against the ray-traced reference vs time");
  struct Args {
    std::string env, csv, plot;
    lab::OpticsReportSettings settings;
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
        args->env.empty() ? lab::builtinTestEnvironment() : optics::loadEnvironment(args->env);
    const lab::OpticsReport report = lab::runOpticsReport(env, args->settings);
    std::cout << "environment: " << (args->env.empty() ? "built-in test environment" : args->env)
              << "\n"
              << lab::formatOpticsReport(report);
    if (!args->csv.empty()) lab::writeOpticsReportCsv(report, args->csv);
    if (!args->plot.empty()) lab::writeOpticsReportPlot(report, args->plot);
    invocation.exitCode = 0;
  });
  addReportDerain(*cmd, invocation);
  addReportEnvmap(*cmd, invocation);
  addReportDepth(*cmd, invocation);
}

}  // namespace pluvia::cli
