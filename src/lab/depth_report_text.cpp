// `pluvia report depth`'s text and CSV (depth_report.h).
#include <fmt/format.h>

#include "lab/depth_report.h"
#include "lab/report_numbers.h"
#include "lab/synthetic_scene.h"

namespace pluvia::lab {

std::string depthRowLabel(const DepthReportRow& row) {
  return fmt::format("{}/{} {}x{} {}", row.framesUsed, row.clipFrames, row.width, row.height,
                     row.frameStep == 0 ? "parallax" : fmt::format("every {}", row.frameStep));
}

std::string formatDepthReport(const DepthReport& report) {
  std::string out;
  out += "GL renderer: " + report.device + "\n";
  out += fmt::format(
      "Synthetic street (lab/synthetic_scene.h) along defaultSyntheticPath: a {:.2f} m walk at "
      "{:g} m, 4° of yaw, {:g}° hfov; frames to COLMAP as 8-bit sRGB PNG, the poses of the others "
      "interpolated; metric scale from the camera height. Depth compared on every {}th frame.\n",
      0.05 * 47, lab::kSyntheticCameraHeightMeters, lab::kSyntheticHfovDeg,
      48 / kDepthReportEvaluationFrames);
  // The columns of the two tables, for the header and each row.
  static constexpr char kPoseColumns[] =
      "{:<26} {:<16} {:>7} {:>6} {:>8} {:>8} {:>8} {:>8} {:>6} {:>7} {:>8} {:>7} {:>7}\n";
  static constexpr char kDepthColumns[] =
      "{:<26} {:>6} {:>7} {:>6} {:>7} {:>7} {:>7} {:>9} {:>11} {:>8} {:>8} {:>9} {:>9} {:>8}\n";
  out += "\n";
  out +=
      fmt::format(kPoseColumns, "used/clip size", "status", "reg", "posed", "rot°mean", "rot°max",
                  "pos m", "pos max", "scale", "level°", "height m", "focal%", "reproj");
  for (const DepthReportRow& row : report.rows) {
    out += fmt::format(kPoseColumns, depthRowLabel(row), row.status,
                       fmt::format("{}/{}", row.registeredUsed, row.framesUsed),
                       fmt::format("{}/{}", row.framesWithPose, row.clipFrames),
                       fixedOrDash(row.rotationMeanDeg, 3), fixedOrDash(row.rotationMaxDeg, 3),
                       fixedOrDash(row.positionMeanMeters, 3),
                       fixedOrDash(row.positionMaxMeters, 3), fixedOrDash(row.scaleRatio, 3),
                       fixedOrDash(row.levelErrorDeg, 2), fixedOrDash(row.heightOffsetMeters, 3),
                       percentOrDash(row.focalError), fixedOrDash(row.reprojectionPx, 2));
  }
  out += "\n";
  out += fmt::format(kDepthColumns, "used/clip size", "frames", "depth%", "p90%", "ground%",
                     "walls%", "boxes%", "sky->inf%", "solid->inf%", "render s", "COLMAP s",
                     "tracking s", "densify/f", "total s");
  for (const DepthReportRow& row : report.rows) {
    out +=
        fmt::format(kDepthColumns, depthRowLabel(row), row.depthFrames,
                    percentOrDash(row.depthMedian), percentOrDash(row.depthP90),
                    percentOrDash(row.depthMedianGround), percentOrDash(row.depthMedianWalls),
                    percentOrDash(row.depthMedianBoxes), percentOrDash(row.skyAsInfinity),
                    percentOrDash(row.nonSkyAsInfinity), fixedOrDash(row.renderSeconds, 1),
                    fixedOrDash(row.colmapSeconds, 1), fixedOrDash(row.trackingSeconds, 1),
                    fixedOrDash(row.densifySecondsPerFrame, 2), fixedOrDash(row.totalSeconds, 1));
  }
  out +=
      "(depth%: median |est - true| / true over pixels both call finite, p90 its 90th "
      "percentile, then the median on ground, walls, boxes; sky->inf: true sky estimated +inf; "
      "solid->inf: the rest estimated +inf; total: tracking without rendering + densifying "
      "every clip frame at the measured rate.)\n";
  for (const DepthReportRow& row : report.rows) {
    if (row.status != "ok" && !row.message.empty())
      out += fmt::format("{}: {}: {}\n", depthRowLabel(row), row.status, row.message);
  }

  // The targets on the default row: the 48-frame 1280x720 clip, frames chosen by parallax.
  for (const DepthReportRow& row : report.rows) {
    if (row.frameStep != 0 || row.width != 1280 || row.height != 720) continue;
    out += fmt::format(
        "\nTargets, the 48-frame 1280x720 clip (frames chosen by parallax): every frame posed: {} "
        "({}/{}); rotation error < "
        "{:g}°: {} (max {}°); median depth error < {:g} %: {} ({} %); under {:g} s: {} ({} s).\n",
        row.framesWithPose == row.clipFrames ? "met" : "NOT met", row.framesWithPose,
        row.clipFrames, kDepthReportRotationTargetDeg,
        row.rotationMaxDeg < kDepthReportRotationTargetDeg ? "met" : "NOT met",
        fixedOrDash(row.rotationMaxDeg, 3), 100.0 * kDepthReportDepthTarget,
        row.depthMedian < kDepthReportDepthTarget ? "met" : "NOT met",
        percentOrDash(row.depthMedian), kDepthReportSecondsTarget,
        row.totalSeconds < kDepthReportSecondsTarget ? "met" : "NOT met",
        fixedOrDash(row.totalSeconds, 1));
  }

  const DepthReportReal& real = report.real;
  if (real.present) {
    out += fmt::format(
        "\nReal photos {}: {} of {} registered ({} %) at {}x{}, hfov guess {:g}°, status {}, "
        "mean reprojection error {} px, baseline/depth {}, {} s (reading, downscaling, COLMAP)"
        "{}\n",
        real.folder, real.registered, real.photos, percentOrDash(real.registeredFraction),
        real.width, real.height, kLundHfovDeg, real.status, fixedOrDash(real.reprojectionPx, 3),
        fixedOrDash(real.baselineOverDepth, 3), fixedOrDash(real.seconds, 1),
        real.note.empty() ? "" : " (" + real.note + ")");
  } else {
    out += "\nReal photos (" + std::string(kLundFolder) + ") skipped: " + real.note + "\n";
  }
  for (const std::string& note : report.notes) out += "note: " + note + "\n";
  return out;
}

void writeDepthReportCsv(const DepthReport& report, const std::string& path) {
  writeReportCsv(
      path,
      "scene,clip_frames,frames_used,width,height,status,registered_used,frames_with_pose,"
      "rotation_mean_deg,rotation_max_deg,position_mean_m,position_max_m,scale_ratio,"
      "level_error_deg,height_offset_m,focal_error,reprojection_px,depth_frames,"
      "depth_median_rel_error,depth_p90_rel_error,depth_median_ground,depth_median_walls,"
      "depth_median_boxes,sky_as_inf_fraction,nonsky_as_inf_fraction,render_seconds,"
      "colmap_seconds,tracking_seconds,densify_seconds_per_frame,total_seconds",
      [&](std::ostream& file) {
        for (const DepthReportRow& row : report.rows) {
          file << fmt::format(
              "synthetic,{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}"
              ",{},{}"
              ","
              "{},{}\n",
              row.clipFrames, row.framesUsed, row.width, row.height, row.status, row.registeredUsed,
              row.framesWithPose, csvNumber(row.rotationMeanDeg), csvNumber(row.rotationMaxDeg),
              csvNumber(row.positionMeanMeters), csvNumber(row.positionMaxMeters),
              csvNumber(row.scaleRatio), csvNumber(row.levelErrorDeg),
              csvNumber(row.heightOffsetMeters), csvNumber(row.focalError),
              csvNumber(row.reprojectionPx), row.depthFrames, csvNumber(row.depthMedian),
              csvNumber(row.depthP90), csvNumber(row.depthMedianGround),
              csvNumber(row.depthMedianWalls), csvNumber(row.depthMedianBoxes),
              csvNumber(row.skyAsInfinity), csvNumber(row.nonSkyAsInfinity),
              csvNumber(row.renderSeconds), csvNumber(row.colmapSeconds),
              csvNumber(row.trackingSeconds), csvNumber(row.densifySecondsPerFrame),
              csvNumber(row.totalSeconds));
        }
        const DepthReportReal& real = report.real;
        if (real.present) {
          // The same columns: what the photos give (no truth: no pose or depth error).
          file << fmt::format("opensfm_lund,{},{},{},{},{},{},,,,,,,,,,{},,,,,,,,,,{},{},,{}\n",
                              real.photos, real.photos, real.width, real.height, real.status,
                              real.registered, csvNumber(real.reprojectionPx),
                              csvNumber(real.seconds), csvNumber(real.seconds),
                              csvNumber(real.seconds));
        }
      });
}

}  // namespace pluvia::lab
