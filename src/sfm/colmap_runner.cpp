#include "sfm/colmap_runner.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <set>

#include <opencv2/imgcodecs.hpp>

#include "sfm/colmap_model.h"
#include "util/error.h"
#include "util/subprocess.h"

namespace pluvia::sfm {
namespace {

const char* kStage = "sfm";
namespace stdfs = std::filesystem;

std::string joined(const std::vector<std::string>& argv) {
  std::string text;
  for (const auto& a : argv) text += (text.empty() ? "" : " ") + a;
  return text;
}

// Runs one COLMAP step, appending its command line and output to the log.
// Returns false instead of throwing when `mayFail` (the mapper exits 1 when it builds no model,
// which the caller reports in its own words).
bool runStep(const std::string& step, std::vector<std::string> argv, const stdfs::path& logPath,
             bool mayFail = false) {
  ProcessResult result = runProcess(argv);
  {
    std::ofstream log(logPath, std::ios::app);
    log << "$ " << joined(argv) << "\n" << result.output << "\n[exit " << result.exitCode << "]\n";
    if (!log)
      throw Error("cannot write the COLMAP log " + logPath.string(),
                  {kStage, std::nullopt, logPath.string()});
  }
  if (result.exitCode != 0 && mayFail && result.exitCode != 127) return false;
  if (result.exitCode != 0) {
    // execvp's failure shows up as exit 127 with no output: say so, since the log is then empty.
    std::string hint = result.exitCode == 127 && result.output.empty()
                           ? " (is '" + argv[0] + "' installed? set PLUVIA_COLMAP)"
                           : "";
    throw Error("colmap " + step + " failed with exit code " + std::to_string(result.exitCode) +
                    hint + "; see the log " + logPath.string(),
                {kStage, std::nullopt, logPath.string()});
  }
  return true;
}

// COLMAP reads images from one folder by name, so the frames are linked (or copied where links
// fail) into <workspace>/images.
void stageImages(const ColmapRequest& request, const stdfs::path& folder) {
  stdfs::remove_all(folder);
  stdfs::create_directories(folder);
  std::set<std::string> names;
  for (const auto& image : request.images) {
    std::string name = image.filename().string();
    if (!names.insert(name).second)
      throw Error("colmap: two frames share the file name " + name, {kStage, std::nullopt, name});
    if (!stdfs::exists(image))
      throw Error("colmap: frame file missing: " + image.string(),
                  {kStage, std::nullopt, image.string()});
    std::error_code ec;
    stdfs::create_symlink(stdfs::absolute(image), folder / name, ec);
    if (ec) stdfs::copy_file(image, folder / name, stdfs::copy_options::overwrite_existing);
  }
}

// "f,cx,cy,k" etc. for --ImageReader.camera_params, from the first frame's size.
std::string cameraParams(const ColmapRequest& request) {
  cv::Mat first = cv::imread(request.images.front().string(), cv::IMREAD_UNCHANGED);
  if (first.empty())
    throw Error("colmap: cannot read frame " + request.images.front().string(),
                {kStage, std::nullopt, request.images.front().string()});
  double f = *request.initialFocalPx;
  std::string cx = std::to_string(0.5 * first.cols);
  std::string cy = std::to_string(0.5 * first.rows);
  std::string fs = std::to_string(f);
  const std::string& m = request.cameraModel;
  if (m == "SIMPLE_PINHOLE") return fs + "," + cx + "," + cy;
  if (m == "PINHOLE") return fs + "," + fs + "," + cx + "," + cy;
  if (m == "SIMPLE_RADIAL") return fs + "," + cx + "," + cy + ",0";
  if (m == "RADIAL") return fs + "," + cx + "," + cy + ",0,0";
  throw Error("colmap: no initial focal length support for camera model " + m,
              {kStage, std::nullopt, ""});
}

}  // namespace

namespace {

std::string& defaultColmapProgram() {
  static std::string program;
  return program;
}

}  // namespace

void setColmapProgram(const std::string& program) {
  defaultColmapProgram() = program;
}

std::string colmapProgram(const std::string& requested) {
  if (!requested.empty()) return requested;
  if (!defaultColmapProgram().empty()) return defaultColmapProgram();
  return "colmap";
}

bool colmapAvailable(const std::string& requested) {
  std::string program = colmapProgram(requested);
  if (program.find('/') != std::string::npos) return stdfs::exists(program);
  return programAvailable(program);
}

// One bundle adjustment of the mapped model that frees the focal length and distortion (the
// mapper held them at the request's). The result replaces run.modelFolder unless its focal length
// left the starting one by more than maxFocalRefinementRatio: a wrong field of view in the preset
// is corrected; a drift along the forward-motion ambiguity is not taken.
void refineIntrinsics(const ColmapRequest& request, const std::string& colmap, ColmapRun& run) {
  const stdfs::path binary = request.workspace / "sparse" / run.modelFolder.filename();
  const stdfs::path refined = request.workspace / "refined";
  const stdfs::path refinedText = request.workspace / "text" / "refined";
  stdfs::remove_all(refined);
  stdfs::remove_all(refinedText);
  stdfs::create_directories(refined);
  stdfs::create_directories(refinedText);
  runStep("bundle_adjuster",
          {colmap, "bundle_adjuster", "--input_path", binary.string(), "--output_path",
           refined.string(), "--BundleAdjustment.refine_focal_length", "1",
           "--BundleAdjustment.refine_extra_params", "1"},
          run.logPath);
  runStep("model_converter",
          {colmap, "model_converter", "--input_path", refined.string(), "--output_path",
           refinedText.string(), "--output_type", "TXT"},
          run.logPath);
  const ColmapModel model = readColmapTextModel(refinedText);
  if (model.cameras.empty()) return;
  const double ratio = model.cameras.begin()->second.focalPx() / *request.initialFocalPx;
  if (ratio < request.maxFocalRefinementRatio && ratio > 1.0 / request.maxFocalRefinementRatio) {
    run.modelFolder = refinedText;
    run.focalRefinementRatio = ratio;
  }
}

ColmapRun runColmapSparse(const ColmapRequest& request) {
  if (request.images.empty())
    throw Error("colmap: no frames to reconstruct", {kStage, std::nullopt, ""});
  auto start = std::chrono::steady_clock::now();
  const stdfs::path ws = request.workspace;
  stdfs::create_directories(ws);
  ColmapRun run;
  run.logPath = ws / "colmap.log";
  const stdfs::path imageFolder = ws / "images";
  const stdfs::path database = ws / "database.db";
  const stdfs::path sparse = ws / "sparse";
  const stdfs::path text = ws / "text";
  const bool remap = request.remapOnly && stdfs::exists(database);
  if (!remap) {
    stdfs::remove(run.logPath);
    stdfs::remove(database);
  }
  stdfs::remove_all(sparse);
  stdfs::remove_all(text);
  stdfs::create_directories(sparse);
  if (!remap) stageImages(request, imageFolder);

  const std::string colmap = colmapProgram(request.colmapBinary);
  const std::string threads = std::to_string(request.threads);
  std::vector<std::string> extract = {colmap,
                                      "feature_extractor",
                                      "--database_path",
                                      database.string(),
                                      "--image_path",
                                      imageFolder.string(),
                                      "--ImageReader.single_camera",
                                      "1",
                                      "--ImageReader.camera_model",
                                      request.cameraModel,
                                      "--SiftExtraction.use_gpu",
                                      "0",
                                      "--SiftExtraction.num_threads",
                                      threads,
                                      "--SiftExtraction.max_image_size",
                                      std::to_string(request.maxImageSizePx)};
  if (request.initialFocalPx) {
    extract.insert(extract.end(), {"--ImageReader.camera_params", cameraParams(request)});
  }
  if (!remap) {
    runStep("feature_extractor", extract, run.logPath);
    runStep("sequential_matcher",
            {colmap, "sequential_matcher", "--database_path", database.string(),
             "--SiftMatching.use_gpu", "0", "--SiftMatching.num_threads", threads,
             "--SequentialMatching.overlap", std::to_string(request.sequentialOverlap)},
            run.logPath);
  }
  bool mapped = false;
  const bool fixIntrinsics = request.initialFocalPx && request.fixIntrinsicsWhileMapping;
  std::vector<stdfs::path> models;
  for (int attempt = 0; attempt < std::max(1, request.mapperAttempts) && models.empty();
       ++attempt) {
    stdfs::remove_all(sparse);
    stdfs::create_directories(sparse);
    mapped = runStep("mapper",
                     {colmap,
                      "mapper",
                      "--random_seed",
                      std::to_string(request.firstMapperSeed + attempt),
                      "--database_path",
                      database.string(),
                      "--image_path",
                      imageFolder.string(),
                      "--output_path",
                      sparse.string(),
                      "--Mapper.num_threads",
                      threads,
                      "--Mapper.init_min_tri_angle",
                      std::to_string(request.initMinTriAngleDeg),
                      "--Mapper.init_min_num_inliers",
                      std::to_string(request.initMinInliers),
                      "--Mapper.abs_pose_min_num_inliers",
                      std::to_string(request.absPoseMinInliers),
                      "--Mapper.init_max_forward_motion",
                      std::to_string(request.initMaxForwardMotion),
                      "--Mapper.ba_refine_focal_length",
                      fixIntrinsics ? "0" : "1",
                      "--Mapper.ba_refine_extra_params",
                      fixIntrinsics ? "0" : "1"},
                     run.logPath, true);
    // One numbered folder per disconnected model; the largest is kept below.
    for (const auto& entry : stdfs::directory_iterator(sparse))
      if (entry.is_directory() && stdfs::exists(entry.path() / "images.bin"))
        models.push_back(entry.path());
  }
  run.modelCount = static_cast<int>(models.size());
  if (models.empty())
    throw Error(std::string("colmap mapper built no model") + (mapped ? "" : " and failed") +
                    " after " + std::to_string(std::max(1, request.mapperAttempts)) +
                    " attempts (too little parallax or texture?); see the log " +
                    run.logPath.string(),
                {kStage, std::nullopt, run.logPath.string()});
  size_t best = 0;
  stdfs::path bestFolder;
  for (size_t i = 0; i < models.size(); ++i) {
    stdfs::path out = text / models[i].filename();
    stdfs::create_directories(out);
    runStep("model_converter",
            {colmap, "model_converter", "--input_path", models[i].string(), "--output_path",
             out.string(), "--output_type", "TXT"},
            run.logPath);
    ColmapModel model = readColmapTextModel(out);
    if (bestFolder.empty() || model.images.size() > best) {
      best = model.images.size();
      bestFolder = out;
    }
  }
  run.modelFolder = bestFolder;
  run.intrinsicsHeldWhileMapping = fixIntrinsics;
  if (fixIntrinsics) refineIntrinsics(request, colmap, run);
  // The model used, where a user finds it (depth.colmap_model): <workspace>/model.
  const stdfs::path chosen = ws / "model";
  stdfs::remove_all(chosen);
  stdfs::copy(run.modelFolder, chosen, stdfs::copy_options::recursive);
  run.modelFolder = chosen;
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return run;
}

}  // namespace pluvia::sfm
