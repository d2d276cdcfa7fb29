#include "sfm/clip_tracking.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <map>
#include <set>

#include <fmt/format.h>

#include <opencv2/imgproc.hpp>

#include "image/resize.h"
#include "io/image_file_writer.h"
#include "sfm/colmap_model.h"
#include "sfm/dense_import.h"
#include "sfm/parallax_check.h"
#include "sfm/scale_cues.h"
#include "util/error.h"
#include "util/log.h"
#include "util/timer.h"

namespace pluvia::sfm {
namespace {

// A remapped model replaces a bent one when its bentness is under this share of the first's.
constexpr double kClearlyStraighter = 0.8;

// The registered frame nearest to `frame`: its sparse points are the ones a frame between
// keyframes most likely sees (points hidden from every nearby view are left out).
const SfmKeyframe& nearestKeyframe(const SfmReconstruction& sfm, int64_t frame) {
  const SfmKeyframe* best = &sfm.keyframes.front();
  for (const SfmKeyframe& key : sfm.keyframes)
    if (std::llabs(key.frame - frame) < std::llabs(best->frame - frame)) best = &key;
  return *best;
}

SfmStatus statusFromName(const std::string& name) {
  for (SfmStatus s : {SfmStatus::Ok, SfmStatus::TooFewRegistered, SfmStatus::NoParallax,
                      SfmStatus::NoGroundPlane, SfmStatus::ImplausibleCamera, SfmStatus::Bent})
    if (name == sfmStatusName(s)) return s;
  throw Error("unknown SfM status \"" + name + "\" in cached reconstruction");
}

nlohmann::json cameraJson(const Camera& camera) {
  const Eigen::Quaterniond q(camera.worldFromCamera);
  return {{"width", camera.width},
          {"height", camera.height},
          {"focal_px", camera.focalPx},
          {"principal_point_px", {camera.cx, camera.cy}},
          {"position_m",
           {camera.positionMeters.x(), camera.positionMeters.y(), camera.positionMeters.z()}},
          {"world_from_camera_wxyz", {q.w(), q.x(), q.y(), q.z()}}};
}

// nlohmann writes NaN as null; it reads back as NaN.
double number(const nlohmann::json& json, const char* key) {
  const auto& value = json.at(key);
  return value.is_null() ? NAN : value.get<double>();
}

Camera cameraFromJson(const nlohmann::json& json) {
  Camera camera;
  camera.width = json.at("width").get<int>();
  camera.height = json.at("height").get<int>();
  camera.focalPx = json.at("focal_px").get<double>();
  camera.cx = json.at("principal_point_px").at(0).get<double>();
  camera.cy = json.at("principal_point_px").at(1).get<double>();
  const auto& p = json.at("position_m");
  camera.positionMeters = {p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>()};
  const auto& q = json.at("world_from_camera_wxyz");
  camera.worldFromCamera = Eigen::Quaterniond(q.at(0).get<double>(), q.at(1).get<double>(),
                                              q.at(2).get<double>(), q.at(3).get<double>())
                               .normalized()
                               .toRotationMatrix();
  return camera;
}

// `camera` in a frame whose y = 0 is the fitted ground (a sloping street's, not the level world's):
// what densifySparseDepth's ground bound expects.
Camera cameraOverGround(const SfmReconstruction& sfm, const Camera& camera) {
  const Eigen::Matrix3d level =
      Eigen::Quaterniond::FromTwoVectors(sfm.groundNormal, Eigen::Vector3d::UnitY())
          .toRotationMatrix();
  Camera over = camera;
  over.worldFromCamera = level * camera.worldFromCamera;
  over.positionMeters =
      level * camera.positionMeters + Eigen::Vector3d(0.0, sfm.groundOffsetMeters, 0.0);
  return over;
}

// Where +Y came from and what the scale cues said; each disagreeing cue is a warning.
void logGravityAndScale(const SfmReconstruction& sfm) {
  if (!sfm.groundAtYZero) return;
  std::string cues = fmt::format("structures up to {:.1f} m", sfm.structureHeightMeters);
  if (std::isfinite(sfm.medianCameraSpeedMetersPerSecond))
    cues += fmt::format(", camera speed {:.1f} m/s", sfm.medianCameraSpeedMetersPerSecond);
  double lo = INFINITY, hi = -INFINITY;
  for (const SfmKeyframe& key : sfm.keyframes) {
    lo = std::min(lo, key.heightAboveGroundMeters);
    hi = std::max(hi, key.heightAboveGroundMeters);
  }
  log::info(fmt::format(
      "depth: up from the {}{}; camera heights {:.2f} to {:.2f} m above the ground (standard "
      "deviation {:.1f} % of their mean), which tilts {:.1f} deg from +Y; {}",
      sfm.gravitySource,
      sfm.verticalLineCount > 0 ? fmt::format(" ({} lines)", sfm.verticalLineCount) : "", lo, hi,
      100.0 * sfm.cameraHeightSpread,
      std::acos(std::clamp(sfm.groundNormal.y(), -1.0, 1.0)) * 180.0 / M_PI, cues));
  for (const std::string& warning : sfm.warnings) log::warning("depth: " + warning);
}

}  // namespace

bool keepSecondModel(const SfmReconstruction& first, const SfmReconstruction& second,
                     const SfmOptions& options, std::string& why) {
  const double before = bentness(first, options);
  const double after = second.ok() ? bentness(second, options) : INFINITY;
  const bool keep = after < kClearlyStraighter * before;
  why = second.ok() ? fmt::format(
                          "bentness {:.2f} against the first model's {:.2f} (1: the bound); "
                          "kept the {} model",
                          after, before, keep ? "second" : "first")
                    : fmt::format("the second mapping gave no usable model ({}); kept the first",
                                  second.message);
  return keep;
}

void setKeptModelAside(const std::filesystem::path& workspace) {
  std::filesystem::remove_all(workspace / "model.kept");
  std::filesystem::rename(workspace / "model", workspace / "model.kept");
}

void keepModelFolder(const std::filesystem::path& workspace, bool remapped) {
  const std::filesystem::path kept = workspace / "model.kept";
  if (remapped) {
    std::filesystem::remove_all(kept);
    return;
  }
  std::filesystem::remove_all(workspace / "model");  // absent when the remap built none
  std::filesystem::rename(kept, workspace / "model");
}

void refuseUnusableModel(SfmReconstruction& sfm, const SfmOptions& options) {
  std::string reason;
  const double bent = sfm.ok() ? bentness(sfm, options, &reason) : 0.0;
  if (bent <= options.maxUsableBentness) return;
  sfm.status = SfmStatus::Bent;
  sfm.message = fmt::format(
      "the model is bent beyond use ({}: {:.1f} times the bound, refused past {:g}); its scale "
      "and depth would be wrong",
      reason, bent, options.maxUsableBentness);
}

std::vector<int64_t> trackingFrames(const std::vector<int64_t>& frames, int step) {
  std::vector<int64_t> used;
  const size_t stride = static_cast<size_t>(std::max(1, step));
  for (size_t i = 0; i < frames.size(); i += stride) used.push_back(frames[i]);
  if (!frames.empty() && used.back() != frames.back()) used.push_back(frames.back());
  return used;
}

namespace {

// The frame at most 640 pixels wide, for the parallax measurements.
cv::Mat smallFrame(const Image& image) {
  cv::Mat small;
  const double scale = std::min(1.0, 640.0 / std::max(image.width, image.height));
  cv::resize(rgbMat(image), small, scaledSize(image.width, image.height, scale), 0, 0,
             cv::INTER_AREA);
  return small;
}

// `items` thinned evenly to at most `count`, the first and last kept.
template <typename T>
std::vector<T> thinEvenly(const std::vector<T>& items, size_t count) {
  if (items.size() <= count || count < 2) return items;
  std::vector<T> kept;
  for (size_t k = 0; k < count; ++k) kept.push_back(items[k * (items.size() - 1) / (count - 1)]);
  return kept;
}

}  // namespace

ClipTracking trackClip(const std::vector<int64_t>& frames,
                       const std::function<Image(int64_t)>& readFrame,
                       const ClipTrackingSettings& settings) {
  const auto started = std::chrono::steady_clock::now();
  ClipTracking tracking;
  const size_t maxFrames = static_cast<size_t>(std::max(3, settings.maxFrames));
  // Candidates: every frame when choosing by parallax (every few on very long clips), else every
  // frameStep-th; their small copies feed the parallax measurements.
  const size_t candidateStep = settings.frameStep > 0
                                   ? static_cast<size_t>(settings.frameStep)
                                   : std::max<size_t>(1, frames.size() / (8 * maxFrames) + 1);
  const std::vector<int64_t> candidates = trackingFrames(frames, static_cast<int>(candidateStep));
  std::vector<cv::Mat> small;
  int width = 0;
  for (int64_t frame : candidates) {
    const Image image = readFrame(frame);
    width = image.width;
    small.push_back(smallFrame(image));
  }
  const ParallaxProbe probe(small);
  std::vector<size_t> used(candidates.size());
  for (size_t i = 0; i < used.size(); ++i) used[i] = i;
  if (settings.frameStep == 0) {
    // Too few tracked frames make a weak bundle adjustment (on 5 frames of the synthetic walk
    // COLMAP settled on a quarter of the true focal length): at least minFrames, evenly added.
    const std::vector<size_t> keys = selectKeyframes(probe);
    const std::vector<size_t> even = thinEvenly(used, static_cast<size_t>(settings.minFrames));
    used.clear();
    std::set_union(keys.begin(), keys.end(), even.begin(), even.end(), std::back_inserter(used));
  }
  used = thinEvenly(used, maxFrames);
  for (size_t i : used) tracking.framesUsed.push_back(candidates[i]);

  tracking.sfm.frameCount = static_cast<int>(tracking.framesUsed.size());
  if (tracking.sfm.frameCount < settings.sfm.minRegisteredFrames) {
    tracking.sfm.status = SfmStatus::TooFewRegistered;
    tracking.sfm.message = fmt::format(
        "{} frame{} to track: camera tracking needs at least {}", tracking.sfm.frameCount,
        tracking.sfm.frameCount == 1 ? "" : "s", settings.sfm.minRegisteredFrames);
    return tracking;
  }
  // A pan is refused in a second here rather than by minutes of COLMAP's mapper failing.
  const ParallaxCheck parallax = checkParallax(probe);
  if (parallax.pairsJudged > 0)
    log::info(fmt::format(
        "depth: {:.0f} % of the feature matches show parallax (pan below {:.0f} %); tracking {} "
        "of {} frames",
        100.0 * parallax.parallaxFraction, 100.0 * ParallaxCheckSettings().minParallaxFraction,
        tracking.framesUsed.size(), frames.size()));
  if (parallax.verdict == ParallaxVerdict::NoParallax) {
    tracking.sfm.status = SfmStatus::NoParallax;
    tracking.sfm.message = parallax.message;
    tracking.seconds = secondsSince(started);
    return tracking;
  }

  std::filesystem::create_directories(settings.workspace / "frames");
  ColmapRequest request;
  request.workspace = settings.workspace;
  request.colmapBinary = settings.colmapBinary;
  request.maxImageSizePx = settings.maxImageSizePx;
  std::map<std::string, int64_t> frameOfImage;
  for (int64_t frame : tracking.framesUsed) {
    const Image image = readFrame(frame);
    const std::string name = fmt::format("frame_{:08d}.png", frame);
    const std::filesystem::path path = settings.workspace / "frames" / name;
    const float* rgba = image.rgba.data();
    writeImageFile(path.string(), image.width, image.height,
                   {{"R", rgba, 4}, {"G", rgba + 1, 4}, {"B", rgba + 2, 4}}, {}, frame);
    request.images.push_back(path);
    frameOfImage[name] = frame;
  }
  // Pinhole focal length from the horizontal field of view.
  request.initialFocalPx =
      0.5 * width / std::tan(0.5 * settings.horizontalFovDeg * 3.14159265358979323846 / 180.0);
  // One mapping and its metric model; a focal length far from the preset's field of view is a
  // wrong solution (the 320x180 walk once came back registered, ground found, at a quarter of
  // the true focal length).
  auto map = [&] {
    tracking.run = runColmapSparse(request);
    tracking.sfm =
        reconstructionFromColmap(readColmapTextModel(tracking.run.modelFolder), frameOfImage,
                                 settings.sfm, settings.workspace / "frames");
    const double ratio = tracking.sfm.intrinsics.focalPx / *request.initialFocalPx;
    if (tracking.sfm.status == SfmStatus::Ok && !tracking.sfm.keyframes.empty() &&
        (ratio > settings.maxFocalRatio || ratio < 1.0 / settings.maxFocalRatio)) {
      tracking.sfm.status = SfmStatus::ImplausibleCamera;
      tracking.sfm.message = fmt::format(
          "COLMAP's focal length {:.0f} px is {:.1f} times the {:.0f} px of the preset's field of "
          "view: a wrong reconstruction, or a wrong camera.fov_deg",
          tracking.sfm.intrinsics.focalPx, ratio, *request.initialFocalPx);
    }
  };
  map();
  // A model with no ground below its cameras or an implausible focal length, on a clip whose
  // parallax check passed, is most often the mapper's start gone wrong (the two-fold ambiguity
  // of a ground-dominated first pair): map again, first refining the intrinsics while mapping
  // (which found the right solution on the 320x180 walk where holding them did not, and failed
  // where holding them worked), then with other seeds.
  for (int retry = 1;
       retry <= settings.remapAttempts && (tracking.sfm.status == SfmStatus::NoGroundPlane ||
                                           tracking.sfm.status == SfmStatus::ImplausibleCamera);
       ++retry) {
    request.fixIntrinsicsWhileMapping = !request.fixIntrinsicsWhileMapping;
    log::info(fmt::format("depth: {}; mapping again ({} of {}), the intrinsics {} while mapping",
                          tracking.sfm.message, retry, settings.remapAttempts,
                          request.fixIntrinsicsWhileMapping ? "held" : "refined"));
    request.remapOnly = true;
    request.firstMapperSeed = retry * request.mapperAttempts;
    const ClipTracking before = tracking;
    try {
      map();
    } catch (const Error& e) {
      // No model this time: the previous (refused) result stands unless a later retry succeeds.
      tracking = before;
      log::info(fmt::format("depth: mapping again failed: {}", e.what()));
    }
  }
  // A model that built bent (the mapper's threads sum in their own order, and a different start
  // can straighten it) is mapped again on one thread with other seeds, up to bentRemaps times
  // until one is bent no more, the straightest kept. The remaps also turn the intrinsics the
  // other way: a forward walk pins the focal length poorly, and held at a preset's field of view
  // far from the lens's it bends the walk (Lund's 29 photos: held at 858 px, three of eight runs
  // bent past use; refined while mapping from the same matches, the mapper found 593 to 596 px
  // and heights spreading 9.4 and 9.9 %, though one seed registered only 12 of 29 photos).
  std::string bent;
  if (tracking.sfm.ok() && bentness(tracking.sfm, settings.sfm, &bent) > 1.0) {
    // The other way from the model's own mapping (a failed no-ground retry may have turned the
    // request since).
    request.fixIntrinsicsWhileMapping = !tracking.run.intrinsicsHeldWhileMapping;
    request.remapOnly = true;
    request.threads = 1;
    for (int remap = 1;
         remap <= settings.bentRemaps && bentness(tracking.sfm, settings.sfm, &bent) > 1.0;
         ++remap) {
      log::info(fmt::format(
          "depth: the model looks bent ({}); mapping again on one thread ({} of {}), the "
          "intrinsics {} while mapping",
          bent, remap, settings.bentRemaps,
          request.fixIntrinsicsWhileMapping ? "held" : "refined"));
      const ClipTracking best = tracking;
      setKeptModelAside(settings.workspace);
      request.firstMapperSeed = (settings.remapAttempts + remap) * request.mapperAttempts;
      try {
        map();
      } catch (const Error& e) {
        tracking.sfm.status = SfmStatus::TooFewRegistered;
        tracking.sfm.message = e.what();
      }
      std::string why;
      const bool keep = keepSecondModel(best.sfm, tracking.sfm, settings.sfm, why);
      keepModelFolder(settings.workspace, keep);
      if (!keep) tracking = best;
      log::info("depth: mapped again: " + why);
    }
  }
  refuseUnusableModel(tracking.sfm, settings.sfm);
  tracking.seconds = secondsSince(started);
  logGravityAndScale(tracking.sfm);
  return tracking;
}

SfmReconstruction trackingFromModel(const std::filesystem::path& textModelFolder,
                                    const std::vector<int64_t>& frames,
                                    const std::vector<std::string>& files,
                                    const SfmOptions& options) {
  const ColmapModel model = readColmapTextModel(textModelFolder);
  std::map<std::string, int64_t> ownNames, fileNames;
  for (size_t i = 0; i < frames.size(); ++i) {
    ownNames[fmt::format("frame_{:08d}.png", frames[i])] = frames[i];
    if (files.size() == frames.size())
      fileNames[std::filesystem::path(files[i]).filename().string()] = frames[i];
  }
  bool own = false;
  for (const auto& [id, image] : model.images) own = own || ownNames.count(image.name) > 0;
  // Only the frames the model holds count: a model of every few frames (pluvia depth's) has not
  // failed to register the frames between.
  std::map<std::string, int64_t> inModel;
  for (const auto& [id, image] : model.images) {
    const auto& names = own ? ownNames : fileNames;
    if (auto it = names.find(image.name); it != names.end()) inModel.insert(*it);
  }
  // The façade lines need the images by the model's names: the sequence's own files, else the
  // frames a kept pluvia workspace holds beside its model (<workspace>/frames, <workspace>/model).
  std::filesystem::path imageFolder;
  for (const std::filesystem::path& folder :
       {files.empty() ? std::filesystem::path() : std::filesystem::path(files[0]).parent_path(),
        textModelFolder.parent_path() / "frames"})
    if (!inModel.empty() && !folder.empty() &&
        std::filesystem::exists(folder / inModel.begin()->first)) {
      imageFolder = folder;
      break;
    }
  SfmReconstruction sfm = reconstructionFromColmap(model, inModel, options, imageFolder);
  logGravityAndScale(sfm);
  refuseUnusableModel(sfm, options);
  return sfm;
}

std::optional<std::vector<float>> denseFrameDepth(const SfmReconstruction& sfm,
                                                  const std::filesystem::path& denseWorkspace,
                                                  int64_t frame, int width, int height) {
  for (const SfmKeyframe& key : sfm.keyframes) {
    if (key.frame != frame) continue;
    const std::filesystem::path path = colmapDepthMapPath(denseWorkspace, key.imageName);
    if (!std::filesystem::exists(path)) return std::nullopt;
    int mapWidth = 0, mapHeight = 0;
    std::vector<float> depth =
        importColmapDepthMeters(path, sfm.modelToWorld.scale, &mapWidth, &mapHeight);
    if (mapWidth == width && mapHeight == height) return depth;
    cv::Mat resized;
    cv::resize(cv::Mat(mapHeight, mapWidth, CV_32F, depth.data()), resized, cv::Size(width, height),
               0, 0, cv::INTER_NEAREST);
    return std::vector<float>(resized.begin<float>(), resized.end<float>());
  }
  return std::nullopt;
}

std::vector<float> trackedFrameDepth(const SfmReconstruction& sfm, int64_t frame,
                                     const Image& image, const DensifyOptions& options) {
  if (sfm.keyframes.empty())
    return std::vector<float>(static_cast<size_t>(image.width) * image.height, INFINITY);
  const Camera camera = sfm.path.cameraAt(static_cast<double>(frame));
  const auto samples =
      projectSparsePoints(camera, sfm.pointsMeters, &nearestKeyframe(sfm, frame).visiblePoints);
  // Where the world stands on the fitted ground, the ground bounds the depth from behind and fills
  // the bottom of the frame where blur left no points.
  DensifyOptions withGround = options;
  if (sfm.groundAtYZero && !withGround.groundCamera)
    withGround.groundCamera = cameraOverGround(sfm, camera);
  return densifySparseDepth(samples, image, withGround);
}

std::vector<float> colmapFrameDepth(const SfmReconstruction& sfm, int64_t frame, const Image& image,
                                    const std::filesystem::path& denseWorkspace) {
  std::optional<std::vector<float>> dense;
  if (!denseWorkspace.empty())
    dense = denseFrameDepth(sfm, denseWorkspace, frame, image.width, image.height);
  if (!dense) return trackedFrameDepth(sfm, frame, image);
  if (std::none_of(dense->begin(), dense->end(), [](float d) { return std::isnan(d); }))
    return *dense;
  const std::vector<float> sparse = trackedFrameDepth(sfm, frame, image);
  for (size_t i = 0; i < dense->size(); ++i)
    if (std::isnan((*dense)[i])) (*dense)[i] = sparse[i];
  return *dense;
}

nlohmann::json reconstructionToJson(const SfmReconstruction& sfm) {
  nlohmann::json keys = nlohmann::json::array();
  for (const SfmKeyframe& key : sfm.keyframes)
    keys.push_back({{"frame", key.frame},
                    {"image", key.imageName},
                    {"camera", cameraJson(key.camera)},
                    {"height_above_ground_m", key.heightAboveGroundMeters},
                    {"visible_points", key.visiblePoints}});
  std::vector<double> points;
  points.reserve(sfm.pointsMeters.size() * 3);
  for (const Eigen::Vector3d& p : sfm.pointsMeters)
    points.insert(points.end(), {p.x(), p.y(), p.z()});
  return {{"status", sfmStatusName(sfm.status)},
          {"message", sfm.message},
          {"intrinsics", cameraJson(sfm.intrinsics)},
          {"keyframes", keys},
          {"points_m_xyz", points},
          {"frame_count", sfm.frameCount},
          {"registered_count", sfm.registeredCount},
          {"registered_fraction", sfm.registeredFraction},
          {"mean_reprojection_error_px", sfm.meanReprojectionErrorPx},
          {"baseline_over_depth", sfm.baselineOverDepth},
          {"median_depth_m", sfm.medianDepthMeters},
          {"meters_per_model_unit", sfm.modelToWorld.scale},
          {"ground_at_y_zero", sfm.groundAtYZero},
          {"ground_normal", {sfm.groundNormal.x(), sfm.groundNormal.y(), sfm.groundNormal.z()}},
          {"ground_offset_m", sfm.groundOffsetMeters},
          {"gravity_source", sfm.gravitySource},
          {"vertical_line_count", sfm.verticalLineCount},
          {"ground_tilt_from_vertical_deg", sfm.groundTiltFromVerticalDeg},
          {"structure_height_m", sfm.structureHeightMeters},
          {"median_camera_speed_m_s", sfm.medianCameraSpeedMetersPerSecond},
          {"warnings", sfm.warnings}};
}

SfmReconstruction reconstructionFromJson(const nlohmann::json& json) {
  SfmReconstruction sfm;
  sfm.status = statusFromName(json.at("status").get<std::string>());
  sfm.message = json.at("message").get<std::string>();
  sfm.intrinsics = cameraFromJson(json.at("intrinsics"));
  std::vector<CameraPathKey> keys;
  for (const auto& k : json.at("keyframes")) {
    SfmKeyframe key;
    key.frame = k.at("frame").get<int64_t>();
    key.imageName = k.at("image").get<std::string>();
    key.camera = cameraFromJson(k.at("camera"));
    key.heightAboveGroundMeters = number(k, "height_above_ground_m");
    key.visiblePoints = k.at("visible_points").get<std::vector<int>>();
    keys.push_back({static_cast<double>(key.frame), key.camera.positionMeters,
                    Eigen::Quaterniond(key.camera.worldFromCamera)});
    sfm.keyframes.push_back(std::move(key));
  }
  const auto points = json.at("points_m_xyz").get<std::vector<double>>();
  if (points.size() % 3 != 0) throw Error("cached reconstruction: points_m_xyz is not xyz triples");
  for (size_t i = 0; i + 2 < points.size(); i += 3)
    sfm.pointsMeters.emplace_back(points[i], points[i + 1], points[i + 2]);
  for (const SfmKeyframe& key : sfm.keyframes)
    for (int index : key.visiblePoints)
      if (index < 0 || static_cast<size_t>(index) >= sfm.pointsMeters.size())
        throw Error("cached reconstruction: a visible point index is out of range");
  sfm.frameCount = json.at("frame_count").get<int>();
  sfm.registeredCount = json.at("registered_count").get<int>();
  sfm.registeredFraction = json.at("registered_fraction").get<double>();
  sfm.meanReprojectionErrorPx = json.at("mean_reprojection_error_px").get<double>();
  sfm.baselineOverDepth = json.at("baseline_over_depth").get<double>();
  sfm.medianDepthMeters = json.at("median_depth_m").get<double>();
  sfm.modelToWorld.scale = json.at("meters_per_model_unit").get<double>();
  sfm.groundAtYZero = json.at("ground_at_y_zero").get<bool>();
  const auto& normal = json.at("ground_normal");
  sfm.groundNormal = {normal.at(0).get<double>(), normal.at(1).get<double>(),
                      normal.at(2).get<double>()};
  sfm.groundOffsetMeters = json.at("ground_offset_m").get<double>();
  sfm.gravitySource = json.at("gravity_source").get<std::string>();
  sfm.verticalLineCount = json.at("vertical_line_count").get<int>();
  sfm.groundTiltFromVerticalDeg = number(json, "ground_tilt_from_vertical_deg");
  sfm.structureHeightMeters = number(json, "structure_height_m");
  sfm.medianCameraSpeedMetersPerSecond = number(json, "median_camera_speed_m_s");
  sfm.warnings = json.at("warnings").get<std::vector<std::string>>();
  sfm.path = keys.empty() ? CameraPath::fixed(sfm.intrinsics)
                          : CameraPath::fromRotations(sfm.intrinsics, std::move(keys));
  return sfm;
}

nlohmann::json posesJson(const SfmReconstruction& sfm, const std::vector<int64_t>& frames) {
  nlohmann::json poses = nlohmann::json::array();
  std::set<int64_t> registered;
  for (const SfmKeyframe& key : sfm.keyframes) registered.insert(key.frame);
  for (int64_t frame : frames) {
    const Camera camera = sfm.path.cameraAt(static_cast<double>(frame));
    const Eigen::Quaterniond q(camera.worldFromCamera);
    poses.push_back(
        {{"frame", frame},
         {"registered", registered.count(frame) > 0},
         {"position_m",
          {camera.positionMeters.x(), camera.positionMeters.y(), camera.positionMeters.z()}},
         {"world_from_camera_wxyz", {q.w(), q.x(), q.y(), q.z()}},
         {"focal_px", camera.focalPx},
         {"principal_point_px", {camera.cx, camera.cy}}});
  }
  return {{"convention", "pluvia: metres, +Y up, camera looks down -Z, ground at y = 0"},
          {"registered_fraction", sfm.registeredFraction},
          {"mean_reprojection_error_px", sfm.meanReprojectionErrorPx},
          {"baseline_over_depth", sfm.baselineOverDepth},
          {"meters_per_model_unit", sfm.modelToWorld.scale},
          {"note", sfm.message},
          {"frames", poses}};
}

}  // namespace pluvia::sfm
