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

}  // namespace pluvia::lab
