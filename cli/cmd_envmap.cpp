// `pluvia envmap`: the environment lighting of a shot (Wang et al. section 4.1) as SH
// coefficients, from its own frames stitched into a panorama, or from an equirect HDR.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "common.h"
#include "envmap/clip_environment.h"
#include "io/image_file_writer.h"
#include "io/output_target.h"
#include "optics/environment_file.h"
#include "pluvia/version.h"
#include "util/error.h"
#include "util/fs.h"
#include "util/log.h"

namespace pluvia::cli {
namespace {

void writePanorama(const EquirectMap& map, const std::string& path) {
  writeImageFile(path, map.width, map.height,
                 {{"R", map.rgb.data(), 3, true},
                  {"G", map.rgb.data() + 1, 3, true},
                  {"B", map.rgb.data() + 2, 3, true}},
                 {{"pluvia:version", kVersion}}, std::nullopt);
}

}  // namespace

void addEnvmapCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand(
      "envmap", "environment lighting of a shot as SH: frames stitched into a panorama");
  struct Args {
    std::string input, output, panorama, hdr, frames, lights;
    envmap::ClipEnvironmentSettings settings;
    std::string motion = "auto";
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("INPUT", args->input,
                  "footage: movie, image sequence or image (not needed with --hdr)");
  cmd->add_option("-o,--output", args->output, "ENV.json: SH per key frame and per frame")
      ->required();
  cmd->add_option("--panorama-out", args->panorama,
                  "the panorama as an equirect EXR (with several keys: a pattern, pano.####.exr)");
  cmd->add_option("--fov", args->settings.horizontalFovDeg, "horizontal field of view, degrees")
      ->check(finiteNumber() & CLI::Range(1.0, 170.0));
  cmd->add_option("--every", args->settings.every, "looming camera: a panorama every N frames")
      ->check(CLI::Range(1, 10000));
  cmd->add_option("--motion", args->motion, "auto, pan, loom or static")->check(CLI::IsMember([] {
    std::vector<std::string> names;
    for (const auto& [name, value] : envmap::kStitchMotionNames) names.push_back(name);
    return names;
  }()));
  cmd->add_option("--order", args->settings.shOrder, "SH order (3: 16 coefficients per channel)")
      ->check(CLI::Range(0, 8));
  cmd->add_option("--frames", args->frames, "FIRST-LAST, in the clip's frame numbers")
      ->check(nonEmptyText());
  cmd->add_option("--lights", args->lights,
                  "JSON file: a list of light sources replacing saturated pixels");
  cmd->add_option("--hdr", args->hdr, "an equirect HDR instead of footage");
  cmd->callback([=, &invocation] {
    envmap::ClipEnvironmentSettings settings = args->settings;
    settings.motion = *envmap::stitchMotionNamed(args->motion);
    if (!args->lights.empty())
      settings.lights = envmap::parseLights(
          nlohmann::json::parse(fs::readInputText(args->lights, "the lights file"), nullptr, false),
          args->lights);
    envmap::ClipEnvironment environment;
    std::vector<int64_t> frames;
    const OutputTarget panorama = OutputTarget::classify(args->panorama);
    // Nothing this command writes may be a file it reads.
    auto refuseOutputsOnto = [&](const std::vector<std::string>& inputs,
                                 const std::vector<int64_t>& keyFrames) {
      refuseOverwritingInput(inputs, "-o", {args->output});
      if (args->panorama.empty()) return;
      std::vector<std::string> panoramas = {args->panorama};
      if (panorama.isSequence())
        for (int64_t f : keyFrames) panoramas.push_back(panorama.pathFor(f));
      refuseOverwritingInput(inputs, "--panorama-out", panoramas);
      // Made as -o's is, and before the work: an unwritable folder fails at once.
      fs::ensureParentFolder(args->panorama, fs::MakeFolders::LastLevel);
    };
    if (!args->hdr.empty()) {
      refuseOutputsOnto({args->hdr}, {0});
      envmap::EnvironmentKey key;
      key.radiance = optics::loadEnvironment(args->hdr);
      key.sh = optics::projectEnvironment(key.radiance, settings.shOrder);
      key.coveredFraction = 1.0;
      environment.motion = "hdr";
      environment.keys.push_back(std::move(key));
    } else {
      if (args->input.empty()) throw UsageError("envmap needs INPUT footage or --hdr FILE");
      auto reader = openClip(args->input);
      int64_t first = INT64_MIN, last = INT64_MAX;
      if (!args->frames.empty()) std::tie(first, last) = parseFrameRange(args->frames);
      for (int64_t f : reader->info().frames)
        if (f >= first && f <= last) frames.push_back(f);
      if (frames.empty())
        throw Error(fmt::format("no frames of {} in {}", args->input, args->frames),
                    {"lighting", {}, args->input});
      refuseOutputsOnto(reader->info().files, frames);
      environment = envmap::buildClipEnvironment(*reader, frames, settings);
    }
    nlohmann::json json = envmap::clipEnvironmentJson(environment, frames);
    json["input"] = args->hdr.empty() ? args->input : args->hdr;
    json["fov_deg"] = settings.horizontalFovDeg;
    if (!args->panorama.empty()) {
      if (environment.keys.size() > 1 && !panorama.isSequence())
        throw UsageError(fmt::format(
            "--panorama-out {}: {} panoramas (a looming camera); give a pattern like pano.####.exr",
            args->panorama, environment.keys.size()));
      for (const envmap::EnvironmentKey& key : environment.keys)
        writePanorama(key.radiance, panorama.pathFor(key.frame));
      json["panorama"] = args->panorama;
    }
    fs::writeTextFile(args->output, json.dump(2) + "\n");
    log::info(fmt::format(
        "envmap: {} ({} panorama{}), covered {:.1f} % of the sphere, {:.1f} s -> {}",
        environment.motion, environment.keys.size(), environment.keys.size() == 1 ? "" : "s",
        100.0 * environment.keys.front().coveredFraction, environment.seconds, args->output));
    invocation.exitCode = 0;
  });
}

}  // namespace pluvia::cli
