// `pluvia report envmap`: environments stitched from a simulated pan against the full HDR, and
// the real weir photos stitched (envmap_report.h says what is measured).
#include "lab/envmap_report.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "envmap/panorama.h"
#include "envmap/perspective_view.h"
#include "image/equirect.h"
#include "image/luminance.h"
#include "image/srgb.h"
#include "io/image_file_writer.h"
#include "lab/log_grid.h"
#include "lab/optics_report.h"
#include "lab/report_numbers.h"
#include "lab/test_environment.h"
#include "optics/drop_radiance_map.h"
#include "optics/drop_shading.h"
#include "optics/environment_file.h"
#include "optics/sh.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace pluvia::lab {

using namespace pluvia::envmap;  // what this file measures
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using Direction = std::array<double, 3>;
constexpr double kDeg = M_PI / 180.0;
constexpr double kTarget = 0.10;       // drop colour error in covered directions
constexpr double kTimeTarget = 30.0;   // seconds to stitch 24 frames of 720p
constexpr double kSunFloor = 0.25;     // the sun: texels above this fraction of the peak
constexpr uchar kPhotoClipCode = 250;  // a JPEG's channel at or above this counts as clipped
const char* const kWeirFolder = "stitching/weir";

double maxChannel(const float* rgb) {
  return std::max({rgb[0], rgb[1], rgb[2]});
}

// The camera's exposure, locked for the shot: average metering, as a reflected-light meter
// does. Over a full turn at the report's pitch (frames every hfov / 2), the mean luminance of
// what an 8-bit camera records (each channel clipped at white) is put at mid-grey; bisection
// on log exposure (the clipped mean rises monotonically with the exposure).
double meterExposure(const EquirectMap& env, const EnvmapReportSettings& settings) {
  constexpr int kGridW = 64, kGridH = 36;  // metering samples per frame
  const double fov = settings.horizontalFovDeg;
  const int frames = int(std::ceil(360.0 / (fov / 2.0)));
  std::vector<std::array<float, 3>> samples;
  for (int i = 0; i < frames; ++i) {
    const CameraPose pose = panPose(i * 360.0 / frames, settings.pitchDeg, fov, kGridW);
    const double gridH = double(kGridW) * settings.frameHeight / settings.frameWidth;
    for (int y = 0; y < kGridH; ++y) {
      for (int x = 0; x < kGridW; ++x) {
        const cv::Vec3d cam((x + 0.5 - 0.5 * kGridW) / pose.focalPx,
                            -((y + 0.5) / kGridH - 0.5) * gridH / pose.focalPx, -1.0);
        cv::Vec3d d = pose.cameraToWorld * cam;
        d /= cv::norm(d);
        samples.push_back(sampleEquirect(env, float(d[0]), float(d[1]), float(d[2])));
      }
    }
  }
  auto meanRecorded = [&](double exposure) {
    double sum = 0.0;
    for (const auto& s : samples) {
      const float clipped[3] = {float(std::min(1.0, s[0] * exposure)),
                                float(std::min(1.0, s[1] * exposure)),
                                float(std::min(1.0, s[2] * exposure))};
      sum += rec709Luminance(clipped);
    }
    return sum / double(samples.size());
  };
  double lo = -40.0, hi = 40.0;  // log exposure
  for (int it = 0; it < 80; ++it) {
    const double mid = 0.5 * (lo + hi);
    (meanRecorded(std::exp(mid)) < settings.midGrey ? lo : hi) = mid;
  }
  return std::exp(0.5 * (lo + hi));
}

EquirectMap scaled(const EquirectMap& map, double factor) {
  EquirectMap out = map;
  for (float& v : out.rgb) v = float(v * factor);
  return out;
}

// What the camera would clip, and the clipped sun as a light source (envmap_report.h).
void measureEnvironment(const EquirectMap& env, const EnvmapReportSettings& settings,
                        EnvmapEnvironment& info) {
  info.width = env.width;
  info.height = env.height;
  info.exposure = meterExposure(env, settings);
  const double clip = 1.0 / info.exposure;
  int px = 0, py = 0;
  double peakMax = -1.0, clipped = 0.0;
  for (int y = 0; y < env.height; ++y) {
    const double omega = equirectTexelSolidAngle(env.width, env.height, y);
    for (int x = 0; x < env.width; ++x) {
      const double m = maxChannel(env.texel(x, y));
      if (m >= clip) clipped += omega;
      if (rec709Luminance(env.texel(x, y)) > info.peak)
        info.peak = rec709Luminance(env.texel(x, y));
      if (m > peakMax) peakMax = m, px = x, py = y;
    }
  }
  info.clippedFraction = clipped / (4.0 * M_PI);
  info.sun = peakMax >= clip;
  if (!info.sun) return;
  // Connected texels around the peak above the threshold (wrapping in longitude).
  const double threshold = std::max(clip, kSunFloor * peakMax);
  std::vector<uint8_t> seen(size_t(env.width) * size_t(env.height), 0);
  std::vector<std::pair<int, int>> stack{{px, py}};
  seen[size_t(py) * size_t(env.width) + size_t(px)] = 1;
  double omegaSum = 0.0;
  std::array<double, 3> power{0, 0, 0};
  while (!stack.empty()) {
    const auto [x, y] = stack.back();
    stack.pop_back();
    const double omega = equirectTexelSolidAngle(env.width, env.height, y);
    omegaSum += omega;
    for (int c = 0; c < 3; ++c) power[size_t(c)] += env.texel(x, y)[c] * omega;
    const std::pair<int, int> next[] = {
        {(x + 1) % env.width, y}, {(x + env.width - 1) % env.width, y}, {x, y - 1}, {x, y + 1}};
    for (const auto& [nx, ny] : next) {
      if (ny < 0 || ny >= env.height) continue;
      uint8_t& s = seen[size_t(ny) * size_t(env.width) + size_t(nx)];
      if (s || maxChannel(env.texel(nx, ny)) < threshold) continue;
      s = 1;
      stack.emplace_back(nx, ny);
    }
  }
  const Direction d = equirectTexelDirection(env.width, env.height, px, py);
  info.sunElevationDeg = std::asin(std::clamp(d[1], -1.0, 1.0)) / kDeg;
  info.sunAzimuthDeg = std::atan2(d[0], -d[2]) / kDeg;
  // The disc of the region's solid angle: 2 pi (1 - cos r) = omega.
  info.sunRadiusDeg = std::acos(std::clamp(1.0 - omegaSum / (2.0 * M_PI), -1.0, 1.0)) / kDeg;
  for (int c = 0; c < 3; ++c) info.sunRadiance[size_t(c)] = float(power[size_t(c)] / omegaSum);
}

Direction sunDirection(const EnvmapEnvironment& info) {
  const double e = info.sunElevationDeg * kDeg, a = info.sunAzimuthDeg * kDeg;
  return {std::cos(e) * std::sin(a), std::sin(e), -std::cos(e) * std::cos(a)};
}

bool covers(const cv::Mat& coverage, const Direction& d) {
  const auto uv = equirectUv(d);
  const int x = std::clamp(int(uv[0] * coverage.cols), 0, coverage.cols - 1);
  const int y = std::clamp(int(uv[1] * coverage.rows), 0, coverage.rows - 1);
  return coverage.at<uchar>(y, x) != 0;
}

// Up to `count` view directions inside the coverage, evenly spread (a Fibonacci set thinned).
std::vector<Direction> coveredDirections(const cv::Mat& coverage, int count) {
  std::vector<Direction> inside;
  for (const Direction& d : fibonacciDirections(count * 40)) {
    if (covers(coverage, d)) inside.push_back(d);
  }
  if (int(inside.size()) <= count) return inside;
  std::vector<Direction> out;
  const double stride = double(inside.size()) / count;
  for (int i = 0; i < count; ++i) out.push_back(inside[size_t(i * stride)]);
  return out;
}

EquirectMap dropMap(const EquirectMap& env) {
  return optics::buildDropRadianceMap(
      env, optics::channelOptics({optics::kWaterEta, optics::kWaterEta, optics::kWaterEta},
                                 optics::kDefaultTerms));
}

double shRelativeError(const optics::ShCoefficients& estimate,
                       const optics::ShCoefficients& reference) {
  double diff = 0.0, norm = 0.0;
  for (size_t i = 0; i < reference.size(); ++i) {
    for (size_t c = 0; c < 3; ++c) {
      diff += std::pow(estimate[i][c] - reference[i][c], 2);
      norm += std::pow(reference[i][c], 2);
    }
  }
  return norm > 0.0 ? std::sqrt(diff / norm) : kNaN;
}

// Mean and worst over the directions of the mean over R, G, B of |estimate - reference| /
// reference.
std::pair<double, double> dropError(const EquirectMap& estimate, const EquirectMap& reference,
                                    const std::vector<Direction>& directions) {
  if (directions.empty()) return {kNaN, kNaN};
  double sum = 0.0, worst = 0.0;
  for (const Direction& d : directions) {
    const auto e = sampleEquirect(estimate, float(d[0]), float(d[1]), float(d[2]));
    const auto r = sampleEquirect(reference, float(d[0]), float(d[1]), float(d[2]));
    double err = 0.0;
    for (size_t c = 0; c < 3; ++c)
      err += std::abs(double(e[c]) - r[c]) / std::max(double(r[c]), 1e-12) / 3.0;
    sum += err;
    worst = std::max(worst, err);
  }
  return {sum / double(directions.size()), worst};
}

double rotationAngleDeg(const cv::Matx33d& a, const cv::Matx33d& b) {
  const cv::Matx33d r = a.t() * b;
  const double c = std::clamp((r(0, 0) + r(1, 1) + r(2, 2) - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) / kDeg;
}

// The map times `scale`, clipped, sRGB-encoded, as an 8-bit PNG.
void writePng(const EquirectMap& map, double scale, const fs::path& path) {
  cv::Mat bgr(map.height, map.width, CV_8UC3);
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      const float* t = map.texel(x, y);
      for (int c = 0; c < 3; ++c) {
        const double v = std::clamp(double(t[c]) * scale, 0.0, 1.0);
        bgr.at<cv::Vec3b>(y, x)[2 - c] = uchar(std::lround(srgbEncode(v) * 255.0));
      }
    }
  }
  if (!cv::imwrite(path.string(), bgr)) throw Error("cannot write the image", {"report", {}, path});
}

void writeExr(const EquirectMap& map, const fs::path& path) {
  writeImageFile(
      path.string(), map.width, map.height,
      {{"R", map.rgb.data(), 3}, {"G", map.rgb.data() + 1, 3}, {"B", map.rgb.data() + 2, 3}}, {},
      std::nullopt);
}

std::vector<fs::path> hdrFiles(const EnvmapReportSettings& settings, EnvmapReport& report) {
  if (!settings.environment.empty()) return {settings.environment};
  if (settings.quick) return {};
  if (settings.sharedData.empty()) {
    report.notes.push_back("no shared data folder: the built-in test environment only");
    return {};
  }
  const fs::path folder = fs::path(settings.sharedData) / "hdr";
  std::vector<fs::path> files;
  if (fs::is_directory(folder)) {
    for (const auto& entry : fs::directory_iterator(folder)) {
      std::string ext = entry.path().extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
      if (ext == ".exr" || ext == ".hdr") files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) report.notes.push_back("no HDR in " + folder.string() + ": built-in only");
  return files;
}

// Each connected region of clipped pixels in each frame as a frame-region light, its radiance
// the mean of the HDR over the region's pixels (times the exposure: the stitched map's units).
std::vector<LightSource> clippedRegionLights(const EquirectMap& env,
                                             const std::vector<PanoramaFrame>& frames,
                                             const std::vector<CameraPose>& poses,
                                             double exposure) {
  std::vector<LightSource> lights;
  for (size_t k = 0; k < frames.size() && k < poses.size(); ++k) {
    const cv::Mat& mask = frames[k].saturated;
    if (mask.empty() || cv::countNonZero(mask) == 0) continue;
    cv::Mat labels, stats, centroids;
    const int count = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
    std::vector<std::array<double, 3>> sum(size_t(count), {0, 0, 0});
    std::vector<double> pixels(size_t(count), 0.0);
    const CameraPose& pose = poses[k];
    for (int y = 0; y < mask.rows; ++y) {
      const int* label = labels.ptr<int>(y);
      for (int x = 0; x < mask.cols; ++x) {
        if (label[x] <= 0) continue;
        const cv::Vec3d cam((x + 0.5 - 0.5 * mask.cols) / pose.focalPx,
                            -(y + 0.5 - 0.5 * mask.rows) / pose.focalPx, -1.0);
        cv::Vec3d d = pose.cameraToWorld * cam;
        d /= cv::norm(d);
        const auto radiance = sampleEquirect(env, float(d[0]), float(d[1]), float(d[2]));
        for (size_t c = 0; c < 3; ++c) sum[size_t(label[x])][c] += radiance[c];
        pixels[size_t(label[x])] += 1.0;
      }
    }
    for (int i = 1; i < count; ++i) {
      LightSource light;
      light.frame = int(k);
      light.region =
          cv::Rect(stats.at<int>(i, cv::CC_STAT_LEFT), stats.at<int>(i, cv::CC_STAT_TOP),
                   stats.at<int>(i, cv::CC_STAT_WIDTH), stats.at<int>(i, cv::CC_STAT_HEIGHT));
      for (size_t c = 0; c < 3; ++c)
        light.radiance[c] = float(sum[size_t(i)][c] / pixels[size_t(i)] * exposure);
      lights.push_back(light);
    }
  }
  return lights;
}

// One environment: the frame-count sweep and the "+ lights" row.
void runEnvironment(const EquirectMap& env, EnvmapEnvironment info,
                    const EnvmapReportSettings& settings, EnvmapReport& report) {
  measureEnvironment(env, settings, info);
  log::info(fmt::format("report envmap: {} (exposure {:.4g})", info.name, info.exposure));
  const optics::ShCoefficients referenceSh = optics::projectEnvironment(env, optics::kPaperShOrder);
  const EquirectMap referenceDrops = dropMap(env);

  const int w = settings.frameWidth, h = settings.frameHeight;
  const double fov = settings.horizontalFovDeg;
  std::map<long, RecordedFrame> recorded;  // by yaw in millidegrees
  auto frameAt = [&](double yaw) -> const RecordedFrame& {
    const long key = std::lround(yaw * 1000.0);
    auto it = recorded.find(key);
    if (it == recorded.end()) {
      it = recorded
               .emplace(key, recordView(env, panPose(yaw, settings.pitchDeg, fov, w), w, h,
                                        info.exposure))
               .first;
    }
    return it->second;
  };

  std::vector<int> counts = settings.frameCounts;
  std::sort(counts.begin(), counts.end());
  std::optional<PanoramaResult> widest;
  std::vector<PanoramaFrame> widestFrames;
  Placement widestPlacement;
  // The stitched map back in the HDR's units, measured against it: SH and drop-colour error in
  // the directions the panorama saw.
  auto measureStitched = [&](EnvmapReportRow& row, const PanoramaResult& result) {
    const EquirectMap stitched = scaled(result.radiance, 1.0 / info.exposure);
    row.shError =
        shRelativeError(optics::projectEnvironment(stitched, optics::kPaperShOrder), referenceSh);
    const std::vector<Direction> directions =
        coveredDirections(result.coverage, settings.directions);
    row.directions = int(directions.size());
    std::tie(row.dropMeanError, row.dropMaxError) =
        dropError(dropMap(stitched), referenceDrops, directions);
  };
  for (int count : counts) {
    EnvmapReportRow row;
    row.environment = info.name;
    row.frames = count;
    row.yawStepDeg = std::min(fov / 2.0, 360.0 / count);
    std::vector<PanoramaFrame> frames;
    std::vector<CameraPose> truth;
    for (int i = 0; i < count; ++i) {
      frames.push_back(frameAt(i * row.yawStepDeg).frame);
      truth.push_back(panPose(i * row.yawStepDeg, settings.pitchDeg, fov, w));
    }
    PlacementSettings placementSettings;
    placementSettings.horizontalFovDeg = fov;
    placementSettings.fallbackYawPerFrameDeg = row.yawStepDeg;
    const auto placeStart = Clock::now();
    Placement placement = placeFrames(frames, placementSettings);
    row.placementSeconds = secondsSince(placeStart);
    row.fromFeatures = placement.fromFeatures;
    if (!placement.fromFeatures)
      log::info(fmt::format("report envmap: {} N={}: fallback placement ({})", info.name, count,
                            placement.note));
    // The stitcher places frame 0 level: features give rotations relative to frame 0, so the
    // placement is turned onto frame 0's true orientation; the fallback assumes a level pan,
    // so the camera's known tilt is applied to each camera.
    const cv::Matx33d tilt = placement.poses[0].cameraToWorld.t() * truth[0].cameraToWorld;
    const cv::Matx33d align = truth[0].cameraToWorld * placement.poses[0].cameraToWorld.t();
    double focalError = 0.0;
    for (size_t i = 0; i < placement.poses.size(); ++i) {
      CameraPose& pose = placement.poses[i];
      pose.cameraToWorld =
          placement.fromFeatures ? align * pose.cameraToWorld : pose.cameraToWorld * tilt;
      row.poseErrorDeg =
          std::max(row.poseErrorDeg, rotationAngleDeg(truth[i].cameraToWorld, pose.cameraToWorld));
      focalError += std::abs(pose.focalPx - truth[i].focalPx) / truth[i].focalPx;
    }
    row.focalError = focalError / double(count);

    EquirectSettings render;
    render.width = settings.panoramaWidth;
    render.fill = UnseenFill::Nearest;  // the paper's; the sky model has its own rows below
    const auto renderStart = Clock::now();
    PanoramaResult result = renderEquirect(frames, placement, render);
    row.renderSeconds = secondsSince(renderStart);
    row.coveredFraction = result.coveredFraction;
    row.fillModel = result.fillModel;

    measureStitched(row, result);
    report.rows.push_back(row);

    if (count == counts.back()) {
      widest = std::move(result);
      widestFrames = std::move(frames);
      widestPlacement = std::move(placement);
    }
  }
  if (!widest) return;
  info.sunSeen = info.sun && covers(widest->coverage, sunDirection(info));

  EquirectSettings lightsRender;
  {
    // The paper's light-source replacement, with the radiances "measured when we captured the
    // video" taken from the HDR: each clipped region of each frame, and the sun where the pan
    // did not see it.
    EnvmapReportRow row = report.rows.back();
    row.lightsRestored = true;
    EquirectSettings& render = lightsRender;
    render.width = settings.panoramaWidth;
    render.fill = UnseenFill::Nearest;
    std::vector<CameraPose> truth;
    for (int i = 0; i < counts.back(); ++i)
      truth.push_back(panPose(i * row.yawStepDeg, settings.pitchDeg, fov, w));
    render.lights = clippedRegionLights(env, widestFrames, truth, info.exposure);
    if (info.sun && !info.sunSeen) {
      LightSource sun;
      sun.direction = sunDirection(info);
      sun.radiusDeg = info.sunRadiusDeg;
      for (size_t c = 0; c < 3; ++c) sun.radiance[c] = float(info.sunRadiance[c] * info.exposure);
      render.lights.push_back(sun);
    }
    row.lights = int(render.lights.size());
    const auto renderStart = Clock::now();
    const PanoramaResult result = renderEquirect(widestFrames, widestPlacement, render);
    row.renderSeconds = secondsSince(renderStart);
    measureStitched(row, result);
    report.rows.push_back(row);
    if (!settings.imagesDir.empty())
      writePng(result.radiance, 1.0,
               fs::path(settings.imagesDir) /
                   fmt::format("{}_stitched_{}_lights.png", info.name, counts.back()));
  }
  // The unseen sphere filled by the sky model (panorama.h) instead of the paper's nearest seen
  // colour the rows above use: as recorded, and with the lights of the "+ lights" row (the sun
  // for the Preetham fit then comes from them).
  const std::vector<LightSource> lights = lightsRender.lights;
  for (const bool withLights : {false, true}) {
    // The nearest-fill row it stands beside: the widest pan as recorded, then "+ lights".
    EnvmapReportRow row = report.rows[report.rows.size() - 2];
    row.skyModelFill = true;
    EquirectSettings render;
    render.width = settings.panoramaWidth;
    render.fill = UnseenFill::SkyModel;
    if (withLights) render.lights = lights;
    const auto renderStart = Clock::now();
    const PanoramaResult result = renderEquirect(widestFrames, widestPlacement, render);
    row.renderSeconds = secondsSince(renderStart);
    row.fillModel = result.fillModel;
    measureStitched(row, result);
    report.rows.push_back(row);
    if (!settings.imagesDir.empty())
      writePng(
          result.radiance, 1.0,
          fs::path(settings.imagesDir) / fmt::format("{}_stitched_{}{}_sky_model.png", info.name,
                                                     counts.back(), withLights ? "_lights" : ""));
  }
  if (!settings.imagesDir.empty()) {
    const fs::path dir(settings.imagesDir);
    writePng(env, info.exposure, dir / fmt::format("{}_full.png", info.name));
    writePng(widest->radiance, 1.0,
             dir / fmt::format("{}_stitched_{}.png", info.name, counts.back()));
    cv::imwrite((dir / fmt::format("{}_coverage_{}.png", info.name, counts.back())).string(),
                widest->coverage);
  }
  report.environments.push_back(info);
}

// The real photos: 8-bit sRGB JPEGs, linearised; placed with the field of view unknown.
void runRealPhotos(const EnvmapReportSettings& settings, EnvmapReport& report) {
  EnvmapRealPhotos& real = report.real;
  const fs::path folder = fs::path(settings.sharedData) / kWeirFolder;
  std::vector<fs::path> files;
  if (fs::is_directory(folder)) {
    for (const auto& entry : fs::directory_iterator(folder)) {
      if (entry.path().extension() == ".jpg") files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    report.notes.push_back("no photos in " + folder.string() + ": real photos left out");
    return;
  }
  std::array<float, 256> decode{};
  for (int i = 0; i < 256; ++i) {
    const double e = i / 255.0;
    decode[size_t(i)] = float(srgbDecode(e));
  }
  std::vector<PanoramaFrame> frames;
  double saturated = 0.0, pixels = 0.0;
  for (const fs::path& file : files) {
    const cv::Mat bgr = cv::imread(file.string(), cv::IMREAD_COLOR);
    if (bgr.empty()) throw Error("cannot read the photo", {"report", {}, file.string()});
    PanoramaFrame frame;
    frame.linearRgb = cv::Mat(bgr.size(), CV_32FC3);
    frame.saturated = cv::Mat(bgr.size(), CV_8UC1);
    for (int y = 0; y < bgr.rows; ++y) {
      for (int x = 0; x < bgr.cols; ++x) {
        const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
        frame.linearRgb.at<cv::Vec3f>(y, x) = {decode[p[2]], decode[p[1]], decode[p[0]]};
        const bool clipped = std::max({p[0], p[1], p[2]}) >= kPhotoClipCode;
        frame.saturated.at<uchar>(y, x) = clipped ? 255 : 0;
        saturated += clipped;
      }
    }
    pixels += double(bgr.total());
    real.width = bgr.cols, real.height = bgr.rows;
    frames.push_back(std::move(frame));
  }
  real.folder = folder.string();
  real.frames = int(frames.size());
  real.saturatedFraction = saturated / pixels;
  PlacementSettings placementSettings;  // the field of view only seeds the estimate
  placementSettings.fallbackYawPerFrameDeg = placementSettings.horizontalFovDeg / 2.0;
  const auto placeStart = Clock::now();
  const Placement placement = placeFrames(frames, placementSettings);
  real.placementSeconds = secondsSince(placeStart);
  real.fromFeatures = placement.fromFeatures;
  real.note = placement.note;
  for (const CameraPose& pose : placement.poses) {
    const cv::Vec3d forward = pose.cameraToWorld * cv::Vec3d(0, 0, -1);
    real.yawDeg.push_back(std::atan2(forward[0], -forward[2]) / kDeg);
    real.pitchDeg.push_back(std::asin(std::clamp(forward[1], -1.0, 1.0)) / kDeg);
    real.focalPx.push_back(pose.focalPx);
    real.hfovDeg.push_back(2.0 * std::atan(0.5 * real.width / pose.focalPx) / kDeg);
  }
  EquirectSettings render;
  render.width = 2 * settings.panoramaWidth;
  const auto renderStart = Clock::now();
  const PanoramaResult result = renderEquirect(frames, placement, render);
  real.renderSeconds = secondsSince(renderStart);
  real.coveredFraction = result.coveredFraction;
  real.present = true;
  if (!settings.imagesDir.empty()) {
    const fs::path dir(settings.imagesDir);
    writePng(result.radiance, 1.0, dir / "weir_panorama.png");
    writeExr(result.radiance, dir / "weir_panorama.exr");
    cv::imwrite((dir / "weir_coverage.png").string(), result.coverage);
  }
}

std::string rowLabel(const EnvmapReportRow& row) {
  if (row.skyModelFill)
    return fmt::format("{}{} sky model", row.frames, row.lightsRestored ? "+lights" : "");
  return row.lightsRestored ? fmt::format("{}+lights", row.frames) : std::to_string(row.frames);
}

}  // namespace

EnvmapReport runEnvmapReport(const EnvmapReportSettings& in) {
  EnvmapReportSettings settings = in;
  if (settings.quick) {
    settings.frameWidth = 640, settings.frameHeight = 360;
    settings.frameCounts = {3, 12};
    settings.panoramaWidth = 512;
    settings.directions = 100;
  }
  if (settings.frameCounts.empty() || settings.frameWidth < 16 || settings.frameHeight < 16)
    throw UsageError("report envmap: no frames to record");
  if (!settings.imagesDir.empty()) fs::create_directories(settings.imagesDir);

  EnvmapReport report;
  report.frameWidth = settings.frameWidth, report.frameHeight = settings.frameHeight;
  report.horizontalFovDeg = settings.horizontalFovDeg, report.pitchDeg = settings.pitchDeg;
  report.panoramaWidth = settings.panoramaWidth;

  const std::vector<fs::path> files = hdrFiles(settings, report);
  if (files.empty()) {
    EnvmapEnvironment info;
    info.name = "builtin", info.path = "built-in test environment";
    runEnvironment(builtinTestEnvironment(), info, settings, report);
  }
  for (const fs::path& file : files) {
    EnvmapEnvironment info;
    info.name = file.stem().string(), info.path = file.string();
    runEnvironment(optics::loadEnvironment(file.string()), info, settings, report);
  }
  if (!settings.quick && settings.environment.empty() && !settings.sharedData.empty() &&
      !runRealPart("report envmap", "real photos", report.notes,
                   [&] { runRealPhotos(settings, report); }))
    report.real.present = false;
  if (!settings.imagesDir.empty())
    report.notes.push_back("images written to " + settings.imagesDir);
  return report;
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
  out += "\n" + fmt::format(kColumns, "environment", "frames", "step°", "feat", "pose°", "focal%",
                            "cover%", "SH err%", "drop mean%", "drop max%", "dirs", "place s",
                            "render s", "total s");
  for (const EnvmapReportRow& row : report.rows) {
    out += fmt::format(kColumns, row.environment, rowLabel(row), fixedOrDash(row.yawStepDeg, 1),
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
      modelLightMeanMet += row.dropMeanError < kTarget;
      worstModelLightMean = std::max(worstModelLightMean, row.dropMeanError);
    } else if (row.skyModelFill) {
      ++modelRows;
      modelMeanMet += row.dropMeanError < kTarget;
      worstModelMean = std::max(worstModelMean, row.dropMeanError);
    } else if (row.lightsRestored) {
      ++lightRows;
      lightMeanMet += row.dropMeanError < kTarget;
      lightMaxMet += row.dropMaxError < kTarget;
      worstLightMean = std::max(worstLightMean, row.dropMeanError);
    } else if (last) {
      ++environments;
      meanMet += row.dropMeanError < kTarget;
      maxMet += row.dropMaxError < kTarget;
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
      out += fmt::format(" (target < {:g} s: {})", kTimeTarget,
                         slowest < kTimeTarget ? "met" : "NOT met");
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

// The plot: same canvas, margins and fonts as the other reports' plots.
void writeEnvmapReportPlot(const EnvmapReport& report, const std::string& path) {
  constexpr int kWidth = 1400, kHeight = 900;
  constexpr int kLeft = 110, kRight = 40, kTop = 60, kBottom = 90;
  constexpr int kPlotW = kWidth - kLeft - kRight, kPlotH = kHeight - kTop - kBottom;
  const auto font = cv::FONT_HERSHEY_SIMPLEX;
  const cv::Scalar palette[] = {{200, 140, 60}, {40, 160, 40}, {40, 40, 220}, {160, 60, 160},
                                {0, 140, 200},  {120, 120, 0}, {90, 90, 90},  {200, 60, 60}};

  double tLo = 1e300, tHi = -1e300, eLo = 1e300, eHi = -1e300;
  for (const EnvmapReportRow& row : report.rows) {
    const double t = row.placementSeconds + row.renderSeconds, e = row.dropMeanError;
    if (!(t > 0.0) || !(e > 0.0) || !std::isfinite(e)) continue;
    tLo = std::min(tLo, t), tHi = std::max(tHi, t), eLo = std::min(eLo, e), eHi = std::max(eHi, e);
  }
  if (tLo > tHi) throw Error("the envmap report has no row to plot", {"report", {}, path});
  const double xLo = std::floor(std::log10(tLo) - 0.1), xHi = std::ceil(std::log10(tHi) + 0.1);
  const double yLo = std::floor(std::log10(std::min(eLo, kTarget)) - 0.1);
  const double yHi = std::ceil(std::log10(std::max(eHi, kTarget)) + 0.1);
  auto at = [&](double t, double e) {
    const double fx = (std::log10(t) - xLo) / (xHi - xLo), fy = (std::log10(e) - yLo) / (yHi - yLo);
    return cv::Point(kLeft + int(std::lround(fx * kPlotW)),
                     kTop + kPlotH - int(std::lround(fy * kPlotH)));
  };

  cv::Mat canvas(kHeight, kWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Rect plot(kLeft, kTop, kPlotW, kPlotH);
  drawLogGridX(canvas, plot, xLo, xHi, [&](double t) { return at(t, std::pow(10.0, yLo)).x; });
  drawLogGridY(
      canvas, plot, yLo, yHi, [&](double e) { return at(std::pow(10.0, xLo), e).y; },
      [](double e) { return fmt::format("{:g} %", 100.0 * e); }, 20);
  const int targetY = at(std::pow(10.0, xLo), kTarget).y;
  cv::line(canvas, {kLeft, targetY}, {kLeft + kPlotW, targetY}, {0, 0, 200}, 1, cv::LINE_AA);
  cv::putText(canvas, "target 10 %", {kLeft + 6, targetY - 6}, font, 0.5, {0, 0, 200});
  cv::rectangle(canvas, {kLeft, kTop}, {kLeft + kPlotW, kTop + kPlotH}, {0, 0, 0});
  cv::putText(canvas, "stitching time: placement + rendering (s, log)",
              {kLeft + kPlotW / 2 - 200, kHeight - 30}, font, 0.6, {0, 0, 0});
  cv::putText(canvas,
              fmt::format("Stitched environment: mean drop colour error in covered directions vs "
                          "time ({}x{} frames, {:g} deg hfov)",
                          report.frameWidth, report.frameHeight, report.horizontalFovDeg),
              {kLeft, 35}, font, 0.7, {0, 0, 0}, 2);

  std::map<std::string, size_t> colourOf;
  std::map<std::string, cv::Point> previous;
  for (const EnvmapReportRow& row : report.rows) {
    const double t = row.placementSeconds + row.renderSeconds, e = row.dropMeanError;
    if (!(t > 0.0) || !(e > 0.0) || !std::isfinite(e)) continue;
    if (!colourOf.count(row.environment)) colourOf.emplace(row.environment, colourOf.size());
    const cv::Scalar colour = palette[colourOf[row.environment] % std::size(palette)];
    const cv::Point p = at(t, e);
    if (row.lightsRestored) {
      cv::drawMarker(canvas, p, colour, cv::MARKER_DIAMOND, 14, 2, cv::LINE_AA);
    } else {
      if (previous.count(row.environment))
        cv::line(canvas, previous[row.environment], p, colour, 2, cv::LINE_AA);
      previous[row.environment] = p;
      cv::circle(canvas, p, 5, colour, cv::FILLED, cv::LINE_AA);
    }
    cv::putText(canvas, rowLabel(row), {p.x + 8, p.y - 6}, font, 0.42, colour);
  }
  int legendY = kTop + 25;
  for (const auto& [name, index] : colourOf) {
    const cv::Scalar colour = palette[index % std::size(palette)];
    cv::circle(canvas, {kLeft + kPlotW - 330, legendY - 4}, 5, colour, cv::FILLED, cv::LINE_AA);
    cv::putText(canvas, name, {kLeft + kPlotW - 318, legendY}, font, 0.5, colour);
    legendY += 22;
  }
  cv::putText(canvas, "diamonds: clipped light sources restored", {kLeft + kPlotW - 330, legendY},
              font, 0.5, {0, 0, 0});
  if (!cv::imwrite(path, canvas))
    throw Error("cannot write the plot (is it a .png path?)", {"report", {}, path});
}

}  // namespace pluvia::lab
