// `pluvia match REFERENCE -o PRESET.json [-p BASE]`: a preset fitted to a clip of real rain
// (lab/rain_match.h): candidates rendered on the reference's own clean plates until their streaks'
// statistics match its rain's, the best written as a preset extending BASE.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "common.h"
#include "image/srgb.h"
#include "io/clip_reader.h"
#include "lab/rain_match.h"
#include "preset/preset.h"
#include "realism_render.h"
#include "stages/plate_shutter.h"
#include "stages/rain_settings.h"
#include "util/error.h"
#include "util/fs.h"
#include "util/log.h"

namespace pluvia::cli {
namespace {

// How deep the base draws its rain for a camera `filmedWidthPx` wide: rain.far_m, or with 0 the
// depth that camera sees rain as streaks by day (stages/rain_settings.h).
double drawnDepthMeters(const Preset& base, int filmedWidthPx) {
  const RainSettings rain = rainSettings(base);
  if (rain.farMeters > 0.0) return rain.farMeters;
  const double focalPx =
      0.5 * filmedWidthPx / std::tan(0.5 * base.number("camera.fov_deg") * M_PI / 180.0);
  return streakDepthMeters(rain, focalPx);
}

// How the preset names its base: a shipped preset by name, anything else by absolute path.
std::string baseReference(const std::string& base) {
  for (const std::string& name : shippedPresetNames())
    if (name == base) return base;
  return std::filesystem::absolute(findPreset(base)).string();
}

nlohmann::json matchedPreset(const lab::RainMatch& match, const std::string& base,
                             const std::string& reference) {
  const lab::RainMatchStep& best = match.steps[match.best];
  const lab::RainLook& look = best.look;
  std::string ratios;
  for (const auto& [name, ratio] : best.ratios)
    ratios += fmt::format("{}{} x{:.2f}", ratios.empty() ? "" : ", ", name, ratio);
  nlohmann::json preset = {
      {"pluvia", 1},
      {"extends", baseReference(base)},
      {"description",
       fmt::format("Matched by pluvia match to the rain of {} (streaks rendered on its own clean "
                   "plates, darken, blur and fog off): typical x{:.2f} ({}){}",
                   reference, best.typical, ratios,
                   match.angleMatched
                       ? std::string()
                       : fmt::format("; its streaks' angle not matched (they spread {:.0f} deg), "
                                     "the wind is the base's",
                                     match.reference.angleSpreadDeg))}};
  // The best step's own overrides: the preset renders exactly what the match measured.
  for (const std::string& assignment : lab::lookOverrides(look)) applyOverride(preset, assignment);
  return preset;
}

}  // namespace

void addMatchCommand(CLI::App& app, Invocation& invocation) {
  auto* cmd = app.add_subcommand(
      "match",
      "a preset fitted to a clip of real rain: rate, shutter, wind and how deep the rain is seen, "
      "rendered on its clean plates until the streaks match");
  struct Args {
    std::string reference, output, base = "moderate";
    lab::RainMatchSettings settings;
  };
  auto args = std::make_shared<Args>();
  cmd->add_option("REFERENCE", args->reference,
                  "real rain footage to match: movie or image sequence (rain.%05d.jpg)")
      ->required();
  cmd->add_option("-o,--output", args->output, "the preset to write, PRESET.json")->required();
  cmd->add_option("-p,--preset", args->base,
                  "the preset the match extends (its look: lens, lights, grading, splashes)")
      ->capture_default_str();
  cmd->add_option("--frames", args->settings.frames, "frames of the reference measured")
      ->check(CLI::Range(3, 10000))
      ->capture_default_str();
  cmd->add_option("--steps", args->settings.steps, "candidates rendered")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cmd->add_option("--width", args->settings.widthPx, "measuring width in pixels")
      ->check(CLI::Range(64, 8192))
      ->capture_default_str();
  cmd->callback([=, &invocation] {
    const std::unique_ptr<ClipReader> referenceReader = openClip(args->reference);
    const ClipInfo reference = referenceReader->info();
    refuseOverwritingInput(reference.files, "-o", {args->output});
    refuseOverwritingInput({findPreset(args->base).string()}, "-o", {args->output});
    // The base's own rain is where the search starts, filmed with its shutter or, where it
    // leaves it to the plate (every shipped base), the reference's own.
    const Preset base = loadPreset(args->base, {});
    lab::RainMatchSettings settings = args->settings;
    settings.clip = args->reference;
    settings.start.rateMmPerHour = base.number("rain.rate_mm_h");
    settings.start.opacity = base.number("rain.opacity");
    settings.minFarMeters = std::max(settings.minFarMeters, 2.0 * base.number("rain.near_m"));
    // far_m 0 (every shipped base): as deep as a camera filming the reference at its own width
    // sees the base's rain.
    settings.start.farMeters =
        std::max(settings.minFarMeters, drawnDepthMeters(base, reference.width));
    const double exposure = base.number("camera.exposure_s");
    if (exposure > 0.0) {
      settings.start.exposureSeconds = exposure;
    } else {
      const PlateShutter shutter = findPlateShutter(reference, reference.fps, [&](int64_t frame) {
        Image image = referenceReader->read(frame);
        if (!reference.isFloat)
          for (size_t i = 0; i < image.rgba.size(); i += 4)
            for (size_t c = 0; c < 3; ++c)
              image.rgba[i + c] = float(srgbDecode(std::clamp(image.rgba[i + c], 0.0f, 1.0f)));
        return image;
      });
      settings.start.exposureSeconds = shutter.seconds;
      log::info(fmt::format("match: the reference's shutter 1/{:.0f} s, {}", 1.0 / shutter.seconds,
                            shutter.source));
    }
    // The base's wind across the view (dir_deg 0 is the camera's right, 90 away from it).
    settings.start.windRightMetersPerSecond =
        base.number("rain.wind.speed_m_s") *
        std::cos(base.number("rain.wind.dir_deg") * M_PI / 180.0);
    // The candidates share the reference's plates: written once, their per-clip analysis cached.
    std::unique_ptr<PlateRenderer> renderer;
    const lab::RainMatch match =
        lab::matchRain(settings, [&](const std::vector<cv::Mat3f>& plates, double fps,
                                     int filmedWidthPx, const std::vector<std::string>& overrides) {
          if (!renderer) renderer = std::make_unique<PlateRenderer>(plates, fps, filmedWidthPx);
          return renderer->render(args->base, overrides);
        });
    std::cout << lab::formatRainMatch(match);
    fs::writeTextFile(args->output,
                      matchedPreset(match, args->base, args->reference).dump(2) + "\n");
    loadPreset(args->output, {});  // what was written resolves
    std::cout << fmt::format("match: typical x{:.3f} -> {}\n", match.steps[match.best].typical,
                             args->output);
    invocation.exitCode = 0;
  });
}

}  // namespace pluvia::cli
