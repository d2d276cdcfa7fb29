// `pluvia report optics`: the table of error against run time of the drop-shading methods.
// `pluvia report derain`: rain extraction against synthetic ground truth and on real footage.
// `pluvia report envmap`: environments stitched from a pan against the full HDR.
// `pluvia report depth`: SfM poses and depth against a synthetic scene's truth, and real photos.
// `pluvia report realism`: rendered rain against real rain footage on the same clean plates.
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "commands.h"
#include "common.h"
#include "io/clip_reader.h"
#include "lab/depth_report.h"
#include "lab/derain_report.h"
#include "lab/envmap_report.h"
#include "lab/fog_report.h"
#include "lab/lights_report.h"
#include "lab/optics_report.h"
#include "lab/realism_report.h"
#include "lab/test_environment.h"
#include "optics/environment_file.h"
#include "optics/skylight_scattering.h"
#include "pipeline/camera_settings.h"
#include "realism_render.h"
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

// The --csv and --plot of a report with a table: the options and the files they ask for.
struct TableFiles {
  std::string csv, plot;

  void addOptions(CLI::App* command, const std::string& plotted) {
    command->add_option("--csv", csv, "also write the table as CSV");
    // Checked before any work: a report runs for minutes before it writes its plot.
    command->add_option("--plot", plot, "also write " + plotted + " as a PNG (PLOT.png)")
        ->check(CLI::Validator(
            [](const std::string& path) {
              return lowerExtension(path) == "png"
                         ? std::string()
                         : "the plot is a PNG: give PLOT.png, not " + path;
            },
            "PLOT.png"));
  }
  // Prints the table and writes the files asked for.
  template <class Report>
  void show(const Report& report, std::string (*format)(const Report&),
            void (*writeCsv)(const Report&, const std::string&),
            void (*writePlot)(const Report&, const std::string&)) const {
    std::cout << format(report);
    if (!csv.empty()) writeCsv(report, csv);
    if (!plot.empty()) writePlot(report, plot);
  }
};

// --data (see sharedDataFolder); `withoutIt` says what the report leaves out without the folder.
void addDataOption(CLI::App* command, std::string& data, const std::string& withoutIt) {
  command->add_option("--data", data,
                      "shared data folder (default: $PLUVIA_SHARED_DATA, else ../shared/data "
                      "beside the install prefix or the current directory); " +
                          withoutIt);
}

// The arguments of a report over the shared data with a table and preview images: --csv/--plot,
// --images, --data and --quick, and the report's `Settings` (with sharedData, imagesDir, quick).
template <class Settings>
struct DataReportArgs {
  TableFiles files;
  std::string images, data;
  Settings settings;

  void addOptions(CLI::App* command, const std::string& plotted, const std::string& imagesHelp,
                  const std::string& withoutData, const std::string& quickHelp) {
    files.addOptions(command, plotted);
    command->add_option("--images", images, imagesHelp);
    addDataOption(command, data, withoutData);
    command->add_flag("--quick", settings.quick, quickHelp);
  }
  // The settings with --data resolved (sharedDataFolder: a UsageError when it is no folder) and
  // --images.
  Settings resolved() const {
    Settings resolved = settings;
    resolved.sharedData = sharedDataFolder(data);
    resolved.imagesDir = images;
    return resolved;
  }
};

void addReportDerain(CLI::App& report) {
  auto* derain = report.add_subcommand(
      "derain", "rain extraction: error vs time against synthetic truth, and on real footage");
  auto args = std::make_shared<DataReportArgs<lab::DerainReportSettings>>();
  args->addOptions(derain, "PSNR vs time",
                   "write previews here (PNG): clean plates, mattes x4, input frames",
                   "without it only the example plate is used",
                   "one 320x240 case, short sweeps, no real footage (for tests)");
  derain->callback([=] {
    lab::DerainReportSettings settings = args->resolved();
    settings.examplePlate = findBesideInstall("examples/street/street_plate.mp4");
    const lab::DerainReport result = lab::runDerainReport(settings);
    args->files.show(result, lab::formatDerainReport, lab::writeDerainReportCsv,
                     lab::writeDerainReportPlot);
  });
}

void addReportEnvmap(CLI::App& report) {
  auto* envmap = report.add_subcommand(
      "envmap", "environments stitched from a pan: SH and drop colour error vs frames and time");
  auto args = std::make_shared<DataReportArgs<lab::EnvmapReportSettings>>();
  envmap->add_option("--env", args->settings.environment,
                     "equirect HDR (default: every HDR in the shared data's hdr/, else a "
                     "built-in test environment with a sun)");
  args->addOptions(envmap, "drop colour error vs time",
                   "write panoramas here (PNG; the real photos' also as EXR)",
                   "without it only the built-in environment is used",
                   "the built-in environment, 640x360 frames, 3 and 12 frames, no photos (for "
                   "tests)");
  envmap->callback([=] {
    const std::string& env = args->settings.environment;
    if (!env.empty() && !std::filesystem::is_regular_file(env))
      throw UsageError("--env: no such file: " + env);
    const lab::EnvmapReport result = lab::runEnvmapReport(args->resolved());
    args->files.show(result, lab::formatEnvmapReport, lab::writeEnvmapReportCsv,
                     lab::writeEnvmapReportPlot);
  });
}

void addReportDepth(CLI::App& report, Invocation& invocation) {
  auto* depth = report.add_subcommand(
      "depth", "camera tracking and depth (COLMAP): pose and depth error vs frames, size, time");
  auto args = std::make_shared<DataReportArgs<lab::DepthReportSettings>>();
  args->addOptions(depth, "rotation and depth error vs time",
                   "write depth vs truth previews here (PNG, the middle frame of each row)",
                   "without it the real photos are skipped",
                   "one row: every 4th of the 48 frames (13) at 1280x720, no real photos (for "
                   "tests)");
  depth->add_option("--workspace", args->settings.workspace,
                    "keep COLMAP's folders (frames, database, models, colmap.log) here, one per "
                    "row (default: a temporary folder, removed unless COLMAP failed)");
  depth->callback([=, &invocation] {
    const lab::DepthReport result = lab::runDepthReport(args->resolved());
    args->files.show(result, lab::formatDepthReport, lab::writeDepthReportCsv,
                     lab::writeDepthReportPlot);
    // The table is printed either way; a row that failed makes the command fail.
    int failed = result.real.status == "failed" ? 1 : 0;
    for (const lab::DepthReportRow& row : result.rows) failed += row.status == "failed" ? 1 : 0;
    if (failed > 0) log::error(fmt::format("report depth: {} of its rows failed", failed));
    invocation.exitCode = failed > 0 ? 1 : 0;
  });
}
// `pluvia report lights`: halos, beams, lit drops and glare against their brute-force
// references, and the stage's tiled halos against every pixel.
void addReportLights(CLI::App& report) {
  auto* lights = report.add_subcommand(
      "lights",
      "local lights: halo, beam, lit-drop and glare error against their references vs time");
  struct Args {
    TableFiles files;
    lab::LightsReportSettings settings;
  };
  auto args = std::make_shared<Args>();
  args->files.addOptions(lights, "error vs time");
  lights->add_option("--samples", args->settings.samples, "(light, ray) pairs per table row")
      ->check(CLI::Range(1, 100000));
  lights->add_option("--trace-rays", args->settings.traceRays, "drop tracer rays per angle")
      ->check(CLI::Range(1, 1 << 26));
  lights->add_flag("--quick", args->settings.quick, "fewer samples (a smoke run)");
  lights->callback([=] {
    lab::LightsReport report = lab::runLightsReport(args->settings);
    args->files.show(report, lab::formatLightsReport, lab::writeLightsReportCsv,
                     lab::writeLightsReportPlot);
  });
}

// `pluvia report fog`: the skylight fog model per table size and the exponential model against
// the ray-marched reference, on the CIE overcast sky and on --env (default: the shared data's
// Venice sunset HDR when present).
void addReportFog(CLI::App& report) {
  auto* fog = report.add_subcommand(
      "fog", "skylight fog: error against the ray-marched reference vs table size and time");
  struct Args {
    std::string env, data;
    lab::FogReportSettings settings;
  };
  auto args = std::make_shared<Args>();
  fog->add_option("--env", args->env, "equirect HDR (default: ../shared/data's Venice sunset)");
  fog->add_option("--data", args->data, "shared data folder");
  fog->add_option("--directions", args->settings.directions, "random view directions")
      ->check(CLI::Range(1, 100000));
  fog->add_option("--rain-extinction", args->settings.rainExtinctionPerMeter, "1/m")
      ->check(CLI::Range(0.0, 10.0));
  fog->add_option("--fog-density", args->settings.fogPerMeter, "1/m")->check(CLI::Range(0.0, 10.0));
  fog->callback([=] {
    std::vector<std::pair<std::string, EquirectMap>> environments;
    environments.emplace_back("CIE overcast (256x128)",
                              optics::cieOvercastSky(256, {1.0f, 1.0f, 1.0f}));
    std::string env = args->env;
    if (env.empty()) {
      const std::string data = sharedDataFolder(args->data);
      const std::string venice = data + "/hdr/polyhaven_venice_sunset_1k.hdr";
      if (!data.empty() && std::filesystem::exists(venice)) env = venice;
    }
    if (!env.empty())
      environments.emplace_back(std::filesystem::path(env).filename().string(),
                                optics::loadEnvironment(env));
    std::cout << fmt::format("medium: rain extinction {} /m (scattering half of it), fog {} /m\n",
                             args->settings.rainExtinctionPerMeter, args->settings.fogPerMeter)
              << lab::formatFogReport(lab::runFogReport(environments, args->settings));
  });
}

// `pluvia report realism [CLIP ...] [-p PRESET ...]`: each preset rendered on the clean plates of
// real rain footage (cli/realism_render.h) and measured against the footage's own rain.
void addReportRealism(CLI::App& report) {
  auto* realism = report.add_subcommand(
      "realism", "rain streaks against real rain footage: coverage, brightness, size, direction");
  struct Args {
    std::vector<std::string> clips, presets, sets;
    DataReportArgs<lab::RealismReportSettings> data;
  };
  auto args = std::make_shared<Args>();
  realism->add_option("clips", args->clips,
                      "real rain clips (movie or sequence; default: NTURain ra1 from the shared "
                      "data)");
  realism->add_option("-p,--preset", args->presets,
                      "presets to render and measure (repeatable; default: every shipped one)");
  realism->add_option("--set", args->sets, "KEY=VALUE applied to every preset (repeatable)");
  realism->add_option("--frames", args->data.settings.frames, "frames measured per clip (24)")
      ->check(CLI::Range(3, 10000));
  args->data.addOptions(realism, "the ratios to real per statistic",
                        "write the contact sheets here (PNG: real | presets, frame and layer)",
                        "without it only the clips given are measured",
                        "8 frames at 320 px wide (for tests)");
  realism->callback([=] {
    lab::RealismReportSettings settings = args->data.resolved();
    settings.clips = args->clips;
    settings.presets = args->presets;
    if (settings.presets.empty())
      for (const std::string& name : shippedPresetNames())
        if (name != "base") settings.presets.push_back(name);
    for (const std::string& preset : settings.presets) loadPreset(preset, args->sets);
    // The clips' frames are inputs: no table or plot is written over one.
    for (const std::string& clip : settings.clips) {
      const std::vector<std::string> files = openClip(clip)->info().files;
      refuseOverwritingInput(files, "--csv", {args->data.files.csv});
      refuseOverwritingInput(files, "--plot", {args->data.files.plot});
    }
    const lab::RealismReport result = lab::runRealismReport(
        settings, [&](const std::vector<cv::Mat3f>& plates, double fps, int filmedWidthPx,
                      double shutterSeconds, const std::string& preset) {
          // A preset that leaves the shutter to the plate films the clip's own.
          std::vector<std::string> sets = args->sets;
          if (cameraSettings(loadPreset(preset, sets)).shutterFromPlate())
            sets.push_back(fmt::format("camera.exposure_s={:.6g}", shutterSeconds));
          return renderOnPlates(plates, fps, filmedWidthPx, preset, sets);
        });
    args->data.files.show(result, lab::formatRealismReport, lab::writeRealismReportCsv,
                          lab::writeRealismReportPlot);
  });
}

}  // namespace

void addReportCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand("report", "measurement reports");
  cmd->require_subcommand(1);
  auto* optics =
      cmd->add_subcommand("optics", "drop shading: error against the ray-traced reference vs time");
  struct Args {
    TableFiles files;
    std::string env;
    lab::OpticsReportSettings settings;
  };
  auto args = std::make_shared<Args>();
  optics->add_option("--env", args->env,
                     "equirect HDR (default: a built-in test environment with a sun)");
  args->files.addOptions(optics, "error vs time");
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
  optics->callback([=] {
    const EquirectMap env =
        args->env.empty() ? lab::builtinTestEnvironment() : optics::loadEnvironment(args->env);
    const lab::OpticsReport report = lab::runOpticsReport(env, args->settings);
    std::cout << "environment: " << (args->env.empty() ? "built-in test environment" : args->env)
              << "\n";
    args->files.show(report, lab::formatOpticsReport, lab::writeOpticsReportCsv,
                     lab::writeOpticsReportPlot);
  });
  addReportDerain(*cmd);
  addReportEnvmap(*cmd);
  addReportDepth(*cmd, invocation);
  addReportLights(*cmd);
  addReportFog(*cmd);
  addReportRealism(*cmd);
}

}  // namespace pluvia::cli
