// `pluvia report depth`: SfM poses and depth against the synthetic street's ground truth, and
// the real opensfm_lund photos (depth_report.h says what is measured).
#include "lab/depth_report.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <memory>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "geometry/camera.h"
#include "geometry/camera_path.h"
#include "image/srgb.h"
#include "lab/log_grid.h"
#include "lab/pose_error.h"
#include "lab/report_numbers.h"
#include "lab/synthetic_scene.h"
#include "sfm/clip_tracking.h"
#include "sfm/colmap_runner.h"
#include "util/error.h"
#include "util/timer.h"

namespace pluvia::lab {

using namespace pluvia::sfm;  // what this file measures
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
constexpr int kLundSizePx = 800;

struct RowSpec {
  int clipFrames, frameStep, width, height;
};

// The encode of an sRGB camera file (8-bit PNG, as COLMAP and a real plate get), clamped 0..1.
float srgbEncode(float linear) {
  return float(pluvia::srgbEncode(std::clamp(linear, 0.0f, 1.0f)));
}

// What each pixel of a true depth map shows: 0 sky, 1 ground, 2 walls (side and back), 3 boxes.
enum Region : uint8_t { kSky = 0, kGround = 1, kWalls = 2, kBoxes = 3 };

std::vector<uint8_t> regionsOf(const Camera& camera, const std::vector<float>& depth,
                               const lab::SyntheticScene& scene) {
  std::vector<uint8_t> regions(depth.size(), kSky);
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      const size_t i = static_cast<size_t>(y) * camera.width + x;
      const double d = depth[i];
      if (!std::isfinite(d)) continue;
      const Eigen::Vector3d p =
          camera.positionMeters + camera.worldFromCamera * (camera.rayCamera(x + 0.5, y + 0.5) * d);
      const double tolerance = 0.02 + 0.002 * d;
      if (std::fabs(p.y()) < tolerance)
        regions[i] = kGround;
      else if (std::fabs(std::fabs(p.x()) - scene.halfWidthMeters) < tolerance ||
               std::fabs(p.z() - scene.backWallZMeters) < tolerance)
        regions[i] = kWalls;
      else
        regions[i] = kBoxes;
    }
  }
  return regions;
}

// Inverse depth as grey (white at 1.5 m, black at infinity) into a BGR8 panel.
cv::Mat inverseDepthPanel(const std::vector<float>& depth, int width, int height) {
  cv::Mat panel(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float d = depth[static_cast<size_t>(y) * width + x];
      double v = std::isfinite(d) && d > 0 ? std::min(1.0, 1.5 / d) : 0.0;
      if (std::isnan(d)) v = 0.0;
      const auto g = static_cast<uchar>(std::lround(255.0 * std::sqrt(v)));
      panel.at<cv::Vec3b>(y, x) = {g, g, g};
    }
  return panel;
}

// Relative depth error as colour: green 0, yellow 10 %, red 25 % and more; blue where one of the
// two is +inf and the other is not, black where both are sky.
cv::Mat errorPanel(const std::vector<float>& truth, const std::vector<float>& estimate, int width,
                   int height) {
  cv::Mat panel(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      const float t = truth[i], e = estimate[i];
      cv::Vec3b colour(0, 0, 0);
      if (std::isfinite(t) != std::isfinite(e)) {
        colour = {220, 80, 0};
      } else if (std::isfinite(t)) {
        const double r = std::min(1.0, std::fabs(e - t) / t / 0.25);
        const double red = std::min(1.0, 2.5 * r), green = r < 0.4 ? 1.0 : 1.0 - (r - 0.4) / 0.6;
        colour = {0, static_cast<uchar>(200 * green), static_cast<uchar>(230 * red)};
      }
      panel.at<cv::Vec3b>(y, x) = colour;
    }
  return panel;
}

void labelPanel(cv::Mat& panel, const std::string& text) {
  const double scale = std::max(0.4, panel.cols / 1600.0);
  cv::putText(panel, text, {10, static_cast<int>(30 * scale) + 4}, cv::FONT_HERSHEY_SIMPLEX, scale,
              {0, 0, 0}, 4, cv::LINE_AA);
  cv::putText(panel, text, {10, static_cast<int>(30 * scale) + 4}, cv::FONT_HERSHEY_SIMPLEX, scale,
              {255, 255, 255}, 1, cv::LINE_AA);
}

// 2 x 2: the frame, the error, the true and the estimated inverse depth.
void writeDepthPreview(const Image& frame, const std::vector<float>& truth,
                       const std::vector<float>& estimate, const std::string& title,
                       const fs::path& path) {
  const int w = frame.width, h = frame.height;
  cv::Mat rgb(h, w, CV_8UC3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float* p = frame.pixel(x, y);
      auto code = [](float v) { return static_cast<uchar>(std::lround(255.0f * srgbEncode(v))); };
      rgb.at<cv::Vec3b>(y, x) = {code(p[2]), code(p[1]), code(p[0])};
    }
  cv::Mat truthPanel = inverseDepthPanel(truth, w, h);
  cv::Mat estimatePanel = inverseDepthPanel(estimate, w, h);
  cv::Mat error = errorPanel(truth, estimate, w, h);
  labelPanel(rgb, title);
  labelPanel(error, "|est - true| / true: green 0, yellow 10 %, red >= 25 %; blue: inf mismatch");
  labelPanel(truthPanel, "true inverse depth (white 1.5 m, black sky)");
  labelPanel(estimatePanel, "SfM densified inverse depth");
  cv::Mat top, bottom, all;
  cv::hconcat(rgb, error, top);
  cv::hconcat(truthPanel, estimatePanel, bottom);
  cv::vconcat(top, bottom, all);
  fs::create_directories(path.parent_path());
  if (!cv::imwrite(path.string(), all)) throw Error("cannot write a preview", {"report", {}, path});
}

DepthReportRow runSyntheticRow(lab::SyntheticSceneRenderer& renderer, const RowSpec& spec,
                               const fs::path& workspace, const DepthReportSettings& settings,
                               DepthReport& report) {
  DepthReportRow row;
  row.clipFrames = spec.clipFrames;
  row.width = spec.width;
  row.height = spec.height;
  const CameraPath truth =
      lab::defaultSyntheticCameraPath(spec.width, spec.height, spec.clipFrames);
  std::vector<int64_t> frames;
  for (int i = 0; i < spec.clipFrames; ++i) frames.push_back(i);
  row.frameStep = spec.frameStep;

  ClipTrackingSettings tracking;
  tracking.workspace = workspace;
  tracking.frameStep = spec.frameStep;
  tracking.horizontalFovDeg = lab::kSyntheticHfovDeg;
  tracking.maxImageSizePx = std::max(1600, std::max(spec.width, spec.height));
  tracking.colmapBinary = settings.colmapBinary;
  tracking.sfm.scale.cameraHeightMeters = lab::kSyntheticCameraHeightMeters;
  double renderSeconds = 0.0;
  auto readFrame = [&](int64_t frame) {
    const auto start = Clock::now();
    Image image = renderer.render(truth.cameraAt(static_cast<double>(frame)));
    for (size_t i = 0; i < image.pixelCount(); ++i)
      for (int c = 0; c < 3; ++c) image.rgba[i * 4 + c] = srgbEncode(image.rgba[i * 4 + c]);
    renderSeconds += secondsSince(start);
    return image;
  };
  std::cerr << fmt::format("report depth: {}: rendering and tracking...\n", depthRowLabel(row));
  ClipTracking tracked;
  try {
    tracked = trackClip(frames, readFrame, tracking);
  } catch (const Error& e) {
    row.status = "failed";
    row.message = e.describe();
    row.renderSeconds = renderSeconds;
    row.rotationMeanDeg = row.rotationMaxDeg = row.positionMeanMeters = row.positionMaxMeters =
        row.scaleRatio = row.levelErrorDeg = row.heightOffsetMeters = row.focalError =
            row.reprojectionPx = row.depthMedian = row.depthP90 = row.depthMedianGround =
                row.depthMedianWalls = row.depthMedianBoxes = row.skyAsInfinity =
                    row.nonSkyAsInfinity = row.colmapSeconds = row.trackingSeconds =
                        row.densifySecondsPerFrame = row.totalSeconds = kNaN;
    report.notes.push_back(fmt::format("{}: COLMAP failed: {}", depthRowLabel(row), row.message));
    return row;
  }
  const SfmReconstruction& sfm = tracked.sfm;
  row.status = sfmStatusName(sfm.status);
  row.message = sfm.message;
  row.framesUsed = static_cast<int>(tracked.framesUsed.size());
  row.registeredUsed = sfm.registeredCount;
  row.reprojectionPx = sfm.meanReprojectionErrorPx;
  row.renderSeconds = renderSeconds;
  row.colmapSeconds = tracked.run.seconds;
  row.trackingSeconds = tracked.seconds - renderSeconds;
  row.focalError = sfm.keyframes.empty()
                       ? kNaN
                       : std::fabs(sfm.intrinsics.focalPx - truth.cameraAt(0).focalPx) /
                             truth.cameraAt(0).focalPx;

  // Poses of the frames between the first and the last registered one.
  std::vector<int> posed;
  if (!sfm.keyframes.empty())
    for (int i = 0; i < spec.clipFrames; ++i)
      if (i >= sfm.keyframes.front().frame && i <= sfm.keyframes.back().frame) posed.push_back(i);
  row.framesWithPose = static_cast<int>(posed.size());
  row.rotationMeanDeg = row.rotationMaxDeg = row.positionMeanMeters = row.positionMaxMeters =
      row.scaleRatio = row.levelErrorDeg = row.heightOffsetMeters = kNaN;
  if (!posed.empty()) {
    std::vector<Camera> trueCameras, estimated;
    for (int i : posed) {
      trueCameras.push_back(truth.cameraAt(i));
      estimated.push_back(sfm.path.cameraAt(i));
    }
    const PoseErrors errors = comparePoses(trueCameras, estimated);
    row.rotationMeanDeg = errors.meanRotationErrorDeg;
    row.rotationMaxDeg = errors.maxRotationErrorDeg;
    row.positionMeanMeters = errors.meanPositionErrorMeters;
    row.positionMaxMeters = errors.maxPositionErrorMeters;
    row.scaleRatio = errors.scaleRatio;
    row.levelErrorDeg = errors.levelErrorDeg;
    row.heightOffsetMeters = errors.heightOffsetMeters;
  }

  // Depth on every clipFrames/6-th frame that has a pose.
  const int evaluationStep = std::max(1, spec.clipFrames / kDepthReportEvaluationFrames);
  const int previewFrame = (spec.clipFrames / 2) / evaluationStep * evaluationStep;
  DepthErrorAccumulator all, byRegion[4];
  double densifySeconds = 0.0;
  for (int frame : posed) {
    if (frame % evaluationStep != 0) continue;
    const Camera camera = truth.cameraAt(frame);
    const Image image = renderer.render(camera);
    const std::vector<float>& trueDepth = *image.findPlane(kDepthPlane);
    const auto start = Clock::now();
    const std::vector<float> depth = trackedFrameDepth(sfm, frame, image);
    densifySeconds += secondsSince(start);
    ++row.depthFrames;
    all.add(trueDepth, depth);
    const std::vector<uint8_t> regions = regionsOf(camera, trueDepth, renderer.scene());
    for (uint8_t region : {kGround, kWalls, kBoxes}) {
      std::vector<uint8_t> mask(regions.size());
      for (size_t i = 0; i < regions.size(); ++i) mask[i] = regions[i] == region;
      byRegion[region].add(trueDepth, depth, &mask);
    }
    if (!settings.imagesDir.empty() && frame == previewFrame) {
      const fs::path path = fs::path(settings.imagesDir) /
                            fmt::format("depth_{}of{}_{}x{}_frame{}.png", row.framesUsed,
                                        row.clipFrames, row.width, row.height, frame);
      writeDepthPreview(image, trueDepth, depth,
                        fmt::format("frame {} of {} ({} to COLMAP), {}x{}", frame, row.clipFrames,
                                    row.framesUsed, row.width, row.height),
                        path);
      report.notes.push_back("wrote " + path.string());
    }
  }
  const DepthErrors depth = all.result();
  row.depthMedian = depth.medianRelativeError;
  row.depthP90 = depth.p90RelativeError;
  row.skyAsInfinity = depth.skyAsInfinityFraction;
  row.nonSkyAsInfinity = depth.nonSkyAsInfinityFraction;
  row.depthMedianGround = byRegion[kGround].result().medianRelativeError;
  row.depthMedianWalls = byRegion[kWalls].result().medianRelativeError;
  row.depthMedianBoxes = byRegion[kBoxes].result().medianRelativeError;
  row.densifySecondsPerFrame = row.depthFrames > 0 ? densifySeconds / row.depthFrames : kNaN;
  row.totalSeconds = row.trackingSeconds + (std::isfinite(row.densifySecondsPerFrame)
                                                ? row.densifySecondsPerFrame * row.clipFrames
                                                : 0.0);
  if (row.depthFrames == 0) {
    row.depthMedian = row.depthP90 = row.skyAsInfinity = row.nonSkyAsInfinity = kNaN;
  }
  return row;
}

// Photos as display-referred 0..1 RGB, downscaled (area) to kLundSizePx on the long side.
Image readPhoto(const fs::path& path) {
  const cv::Mat bgr = cv::imread(path.string(), cv::IMREAD_COLOR);
  if (bgr.empty()) throw Error("cannot read the photo", {"report", {}, path.string()});
  cv::Mat small = bgr;
  const double scale = double(kLundSizePx) / std::max(bgr.cols, bgr.rows);
  if (scale < 1.0) cv::resize(bgr, small, cv::Size(), scale, scale, cv::INTER_AREA);
  Image image(small.cols, small.rows);
  for (int y = 0; y < small.rows; ++y)
    for (int x = 0; x < small.cols; ++x) {
      const cv::Vec3b p = small.at<cv::Vec3b>(y, x);
      float* out = image.pixel(x, y);
      out[0] = p[2] / 255.0f;
      out[1] = p[1] / 255.0f;
      out[2] = p[0] / 255.0f;
    }
  return image;
}

void runRealPhotos(const DepthReportSettings& settings, const fs::path& workspace,
                   DepthReport& report) {
  DepthReportReal& real = report.real;
  if (settings.sharedData.empty()) {
    real.note = "no shared data folder (--data, $PLUVIA_SHARED_DATA or ../shared/data)";
    return;
  }
  const fs::path folder = fs::path(settings.sharedData) / kLundFolder;
  real.folder = folder.string();
  std::vector<fs::path> photos;
  if (fs::is_directory(folder))
    for (const auto& entry : fs::directory_iterator(folder)) {
      std::string ext = entry.path().extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
      if (entry.is_regular_file() && (ext == ".jpg" || ext == ".jpeg"))
        photos.push_back(entry.path());
    }
  if (photos.empty()) {
    real.note = "no photos in " + folder.string();
    return;
  }
  std::sort(photos.begin(), photos.end());
  real.present = true;
  real.photos = static_cast<int>(photos.size());
  std::vector<int64_t> frames;
  for (size_t i = 0; i < photos.size(); ++i) frames.push_back(static_cast<int64_t>(i));
  ClipTrackingSettings tracking;
  tracking.workspace = workspace;
  tracking.horizontalFovDeg = kLundHfovDeg;
  tracking.maxImageSizePx = kLundSizePx;
  tracking.colmapBinary = settings.colmapBinary;
  tracking.sfm.scale.cameraHeightMeters = lab::kSyntheticCameraHeightMeters;
  auto readFrame = [&](int64_t frame) {
    Image image = readPhoto(photos[static_cast<size_t>(frame)]);
    real.width = image.width;
    real.height = image.height;
    return image;
  };
  std::cerr << fmt::format("report depth: {}: {} photos, tracking...\n", folder.string(),
                           photos.size());
  const auto start = Clock::now();
  try {
    const ClipTracking tracked = trackClip(frames, readFrame, tracking);
    real.status = sfmStatusName(tracked.sfm.status);
    real.note = tracked.sfm.message;
    real.registered = tracked.sfm.registeredCount;
    real.registeredFraction = tracked.sfm.registeredFraction;
    real.reprojectionPx = tracked.sfm.meanReprojectionErrorPx;
    real.baselineOverDepth = tracked.sfm.baselineOverDepth;
  } catch (const Error& e) {
    real.status = "failed";
    real.note = e.describe();
    real.registeredFraction = real.reprojectionPx = real.baselineOverDepth = kNaN;
  }
  real.seconds = secondsSince(start);
}

}  // namespace

DepthReport runDepthReport(const DepthReportSettings& settings) {
  if (!colmapAvailable(settings.colmapBinary))
    throw Error("report depth needs COLMAP: \"" + colmapProgram(settings.colmapBinary) +
                "\" was not found (install colmap, or set $PLUVIA_COLMAP to its path)");
  std::vector<RowSpec> specs;
  if (settings.quick)
    // 720p: below it COLMAP settles on a wrong solution for this ground-dominated walk (the
    // full report's 640x360 and 320x180 rows).
    specs = {{48, 4, 1280, 720}};
  else
    // Frames chosen by parallax (the depth stage's default) at three sizes, and every 2nd and
    // 4th frame at 720p. Every frame is left out: 5 cm apart, they made COLMAP settle on a
    // sixth of the focal length after 10 minutes (rotation 1.7 deg, depth 89 % off).
    specs = {{48, 0, 1280, 720},
             {48, 2, 1280, 720},
             {48, 4, 1280, 720},
             {48, 0, 640, 360},
             {48, 0, 320, 180}};

  DepthReport report;
  const fs::path workspace =
      settings.workspace.empty()
          ? fs::temp_directory_path() / fmt::format("pluvia-report-depth-{}", ::getpid())
          : fs::absolute(settings.workspace);
  if (settings.workspace.empty()) fs::remove_all(workspace);
  bool keepWorkspace = !settings.workspace.empty();
  std::unique_ptr<lab::SyntheticSceneRenderer> renderer;
  for (size_t i = 0; i < specs.size(); ++i) {
    const RowSpec& spec = specs[i];
    if (!renderer || i == 0 || specs[i - 1].width != spec.width ||
        specs[i - 1].height != spec.height) {
      renderer.reset();
      renderer = std::make_unique<lab::SyntheticSceneRenderer>(spec.width, spec.height);
      if (report.device.empty()) report.device = renderer->deviceDescription();
    }
    DepthReportRow row =
        runSyntheticRow(*renderer, spec, workspace / fmt::format("row{}", i), settings, report);
    keepWorkspace = keepWorkspace || row.status == "failed";
    report.rows.push_back(std::move(row));
  }
  renderer.reset();
  if (settings.quick)
    report.real.note = "--quick";
  else
    runRealPhotos(settings, workspace / "opensfm_lund", report);
  if (report.real.status == "failed") keepWorkspace = true;
  if (keepWorkspace)
    report.notes.push_back("COLMAP workspaces (logs) kept in " + workspace.string());
  else
    fs::remove_all(workspace);
  return report;
}

}  // namespace pluvia::lab
