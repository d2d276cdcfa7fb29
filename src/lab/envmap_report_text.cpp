// `pluvia report envmap`'s text and CSV (envmap_report.h).
#include <algorithm>
#include <array>
#include <map>

#include <fmt/format.h>

#include "lab/envmap_report.h"
#include "lab/report_numbers.h"

namespace pluvia::lab {

std::string envmapRowLabel(const EnvmapReportRow& row) {
  if (row.skyModelFill)
    return fmt::format("{}{} sky model", row.frames, row.lightsRestored ? "+lights" : "");
  return row.lightsRestored ? fmt::format("{}+lights", row.frames) : std::to_string(row.frames);
}

namespace {

// Per environment, its rows at the most frames under each unseen fill, with and without the
// lights: drop colour mean (max) error.
std::string formatUnseenFillTable(const EnvmapReport& report) {
  std::string out = fmt::format(
      "\nUnseen fill at the most frames, drop colour mean (max) error, as recorded and with "
      "the lights:\n  {:<28} {:>16} {:>16} {:>16} {:>16}  {}\n",
      "environment", "nearest", "sky model", "nearest+lights", "model+lights", "fitted (+lights)");
  // Per environment, its rows at the most frames: nearest, +lights, model, +lights model.
  std::map<std::string, std::array<const EnvmapReportRow*, 4>> byEnvironment;
  std::vector<std::string> order;
  for (const EnvmapReportRow& row : report.rows) {
    if (!byEnvironment.count(row.environment)) order.push_back(row.environment);
    auto& slots = byEnvironment[row.environment];
    const size_t slot = (row.skyModelFill ? 1 : 0) + (row.lightsRestored ? 2 : 0);
    if (!slots[slot] || slots[slot]->frames <= row.frames) slots[slot] = &row;
  }
  auto cell = [](const EnvmapReportRow* row) {
    return row ? fmt::format("{:>7} ({:>6})", percentOrDash(row->dropMeanError),
                             percentOrDash(row->dropMaxError))
               : std::string("-");
  };
  for (const std::string& name : order) {
    const auto& slots = byEnvironment[name];
    if (!slots[1]) continue;
    // "name:": the main table's rows are the ones whose first word is the name.
    out += fmt::format("  {:<28} {:>16} {:>16} {:>16} {:>16}  {}{}\n", name + ":", cell(slots[0]),
                       cell(slots[1]), cell(slots[2]), cell(slots[3]), slots[1]->fillModel,
                       slots[3] ? " (" + slots[3]->fillModel + ")" : "");
  }
  return out;
}

// The real photos' placement, when the report had them.
std::string formatRealPhotos(const EnvmapRealPhotos& real) {
  if (!real.present) return "";
  std::string out = fmt::format(
      "\nReal photos {}: {} of {}x{}, {:.2f} % of pixels clipped; placed {} in {:.2f} s{}, "
      "rendered in {:.2f} s, {:.1f} % of the sphere covered.\n",
      real.folder, real.frames, real.width, real.height, 100.0 * real.saturatedFraction,
      real.fromFeatures ? "from features" : "by the FALLBACK", real.placementSeconds,
      real.note.empty() ? "" : " (" + real.note + ")", real.renderSeconds,
      100.0 * real.coveredFraction);
  out += fmt::format("{:>6} {:>8} {:>8} {:>9} {:>7}\n", "photo", "yaw°", "pitch°", "focal px",
                     "hfov°");
  for (size_t i = 0; i < real.yawDeg.size(); ++i) {
    out += fmt::format("{:>6} {:>8.2f} {:>8.2f} {:>9.1f} {:>7.2f}\n", i + 1, real.yawDeg[i],
                       real.pitchDeg[i], real.focalPx[i], real.hfovDeg[i]);
  }
  return out;
}

}  // namespace

std::string formatEnvmapReport(const EnvmapReport& report) {
  std::string out = fmt::format(
      "Environment maps stitched from a pan against the full HDR: frames of {}x{}, {:g}° "
      "horizontal field of view, pitch {:+g}°, yaw step min(hfov/2, 360°/N), 8-bit sRGB with "
      "clipping at one exposure for the shot (average metering: the recorded mean luminance over a "
      "full turn at mid-grey); placed by placeFrames (true "
      "field of view given; placement turned onto frame 0's true tilt), rendered at {}x{}.\n"
      "SH err: relative L2 of the order-3 SH coefficients. drop mean/max: relative error of the "
      "default drop colour (radiance map, eta 1.333) along view directions inside the coverage. "
      "pose°: worst rotation error of a placed camera; focal: mean relative focal error. "
      "feat: placed from features (else the fallback). '+lights': the clipped regions of each "
      "frame given the HDR's mean radiance over them as frame-region lights, and the sun as a "
      "direction light where the pan did not see it (the paper's light-source replacement).\n\n",
      report.frameWidth, report.frameHeight, report.horizontalFovDeg, report.pitchDeg,
      report.panoramaWidth, report.panoramaWidth / 2);
  for (const EnvmapEnvironment& env : report.environments) {
    out += fmt::format(
        "{}: {}x{}, exposure {:.4g}, peak luminance {:.4g}, clipped {:.2f} % of the sphere",
        env.name, env.width, env.height, env.exposure, env.peak, 100.0 * env.clippedFraction);
    if (env.sun) {
      out += fmt::format(
          "; sun at elevation {:.1f}°, azimuth {:.1f}°, radius {:.2f}°, radiance ({:.4g}, "
          "{:.4g}, {:.4g}), {} by the widest pan",
          env.sunElevationDeg, env.sunAzimuthDeg, env.sunRadiusDeg, env.sunRadiance[0],
          env.sunRadiance[1], env.sunRadiance[2], env.sunSeen ? "seen" : "not seen");
    }
    out += "\n";
  }
  // The columns, for the header and each row.
  static constexpr char kColumns[] =
      "{:<28} {:>7} {:>6} {:>5} {:>6} {:>6} {:>7} {:>7} {:>9} {:>9} {:>5} {:>8} "
      "{:>8} {:>8}\n";
  out += "\n";
  out +=
      fmt::format(kColumns, "environment", "frames", "step°", "feat", "pose°", "focal%", "cover%",
                  "SH err%", "drop mean%", "drop max%", "dirs", "place s", "render s", "total s");
  for (const EnvmapReportRow& row : report.rows) {
    out +=
        fmt::format(kColumns, row.environment, envmapRowLabel(row), fixedOrDash(row.yawStepDeg, 1),
                    row.fromFeatures ? "yes" : "no", fixedOrDash(row.poseErrorDeg, 2),
                    percentOrDash(row.focalError), percentOrDash(row.coveredFraction),
                    percentOrDash(row.shError), percentOrDash(row.dropMeanError),
                    percentOrDash(row.dropMaxError), row.directions,
                    fixedOrDash(row.placementSeconds, 2), fixedOrDash(row.renderSeconds, 2),
                    fixedOrDash(row.placementSeconds + row.renderSeconds, 2));
  }

  // The targets, at the most frames of each environment.
  int environments = 0, meanMet = 0, maxMet = 0, lightRows = 0, lightMeanMet = 0, lightMaxMet = 0;
  int modelRows = 0, modelMeanMet = 0, modelLightRows = 0, modelLightMeanMet = 0;
  double worstMean = 0.0, worstLightMean = 0.0, worstModelMean = 0.0, worstModelLightMean = 0.0;
  double slowest = 0.0;
  int mostFrames = 0;
  for (size_t i = 0; i < report.rows.size(); ++i) {
    const EnvmapReportRow& row = report.rows[i];
    const bool last = i + 1 == report.rows.size() ||
                      report.rows[i + 1].environment != row.environment ||
                      report.rows[i + 1].lightsRestored || report.rows[i + 1].skyModelFill;
    if (row.skyModelFill && row.lightsRestored) {
      ++modelLightRows;
      modelLightMeanMet += row.dropMeanError < kEnvmapDropColourTarget;
      worstModelLightMean = std::max(worstModelLightMean, row.dropMeanError);
    } else if (row.skyModelFill) {
      ++modelRows;
      modelMeanMet += row.dropMeanError < kEnvmapDropColourTarget;
      worstModelMean = std::max(worstModelMean, row.dropMeanError);
    } else if (row.lightsRestored) {
      ++lightRows;
      lightMeanMet += row.dropMeanError < kEnvmapDropColourTarget;
      lightMaxMet += row.dropMaxError < kEnvmapDropColourTarget;
      worstLightMean = std::max(worstLightMean, row.dropMeanError);
    } else if (last) {
      ++environments;
      meanMet += row.dropMeanError < kEnvmapDropColourTarget;
      maxMet += row.dropMaxError < kEnvmapDropColourTarget;
      worstMean = std::max(worstMean, row.dropMeanError);
      slowest = std::max(slowest, row.placementSeconds + row.renderSeconds);
      mostFrames = row.frames;
    }
  }
  if (environments > 0) {
    out += fmt::format(
        "\nAt the most frames ({}), clipped as recorded: drop colour within 10 % in covered "
        "directions for {} of {} environments on the mean, {} of {} at every direction (worst "
        "mean {:.1f} %).\n",
        mostFrames, meanMet, environments, maxMet, environments, 100.0 * worstMean);
    if (lightRows > 0) {
      out += fmt::format(
          "With the clipped light sources given their measured radiance: {} of {} on the mean, {} "
          "of {} at every "
          "direction (worst mean {:.1f} %).\n",
          lightMeanMet, lightRows, lightMaxMet, lightRows, 100.0 * worstLightMean);
    }
    if (modelRows > 0) {
      out += fmt::format(
          "With the unseen sphere filled by the sky model (Preetham, CIE overcast or uniform, "
          "fitted to the seen sky, and the seen ground's albedo under it) instead of the nearest "
          "seen colour: {} of {} on the mean (worst mean {:.1f} %).\n",
          modelMeanMet, modelRows, 100.0 * worstModelMean);
      out += fmt::format(
          "With the lights and the sky model (the sun for the fit from the lights): {} of {} on "
          "the mean (worst mean {:.1f} %).\n",
          modelLightMeanMet, modelLightRows, 100.0 * worstModelLightMean);
      out += formatUnseenFillTable(report);
    }
    out += fmt::format("Slowest stitch of {} frames of {}x{} (placement + rendering): {:.2f} s",
                       mostFrames, report.frameWidth, report.frameHeight, slowest);
    if (mostFrames == 24 && report.frameWidth == 1280 && report.frameHeight == 720)
      out += fmt::format(" (target < {:g} s: {})", kEnvmapStitchSecondsTarget,
                         slowest < kEnvmapStitchSecondsTarget ? "met" : "NOT met");
    out += ".\n";
  }

  out += formatRealPhotos(report.real);
  for (const std::string& note : report.notes) out += "note: " + note + "\n";
  return out;
}

namespace {
// A free-text CSV field: its commas become semicolons (readers split on commas).
std::string withoutCommas(std::string text) {
  std::replace(text.begin(), text.end(), ',', ';');
  return text;
}
}  // namespace

void writeEnvmapReportCsv(const EnvmapReport& report, const std::string& path) {
  writeReportCsv(
      path,
      "environment,frames,lights_restored,lights,yaw_step_deg,from_features,pose_error_deg,"
      "focal_error,covered_fraction,sh_error,drop_mean_error,drop_max_error,directions,"
      "placement_seconds,render_seconds,total_seconds,fill,fill_model",
      [&](std::ostream& file) {
        for (const EnvmapReportRow& row : report.rows) {
          file << fmt::format(
              "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", row.environment,
              row.frames, row.lightsRestored ? 1 : 0, row.lights, csvNumber(row.yawStepDeg),
              row.fromFeatures ? 1 : 0, csvNumber(row.poseErrorDeg), csvNumber(row.focalError),
              csvNumber(row.coveredFraction), csvNumber(row.shError), csvNumber(row.dropMeanError),
              csvNumber(row.dropMaxError), row.directions, csvNumber(row.placementSeconds),
              csvNumber(row.renderSeconds), csvNumber(row.placementSeconds + row.renderSeconds),
              row.skyModelFill ? "sky_model" : "nearest", withoutCommas(row.fillModel));
        }
      });
}

}  // namespace pluvia::lab
