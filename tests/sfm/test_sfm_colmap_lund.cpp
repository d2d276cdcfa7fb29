// The real colmap binary: its failure messages, and a sparse reconstruction of 12 street photos
// from ../shared/data/sfm/opensfm_lund (a forward walk down a street), downscaled to 800 px
// (at 640 px the mapper registered all 10 only some of the time).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "sfm/colmap_model.h"
#include "sfm/colmap_runner.h"
#include "sfm/sfm_poses.h"
#include "sfm/sparse_densify.h"
#include "test_support.h"
#include "util/error.h"

using namespace pluvia;
using namespace pluvia::sfm;

TEST(SfmColmap, MissingBinaryErrorNamesStepAndLog) {
  auto dir = test::freshTempDir("sfm_colmap_missing");
  cv::Mat img(32, 32, CV_8UC3, cv::Scalar(1, 2, 3));
  cv::imwrite((dir / "a.png").string(), img);
  ColmapRequest request;
  request.images = {dir / "a.png"};
  request.workspace = dir / "ws";
  request.colmapBinary = (dir / "no-such-colmap").string();
  EXPECT_FALSE(colmapAvailable(request.colmapBinary));
  try {
    runColmapSparse(request);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    std::string message = e.what();
    EXPECT_NE(message.find("feature_extractor"), std::string::npos) << message;
    EXPECT_NE(message.find((dir / "ws" / "colmap.log").string()), std::string::npos) << message;
    EXPECT_NE(message.find("exit code 127"), std::string::npos) << message;
    EXPECT_TRUE(std::filesystem::exists(dir / "ws" / "colmap.log"));
  }
}

TEST(SfmColmap, EnvironmentOverridesTheProgram) {
  setenv("PLUVIA_COLMAP", "/nonexistent/colmap", 1);
  EXPECT_EQ(colmapProgram(), "/nonexistent/colmap");
  EXPECT_EQ(colmapProgram("mine"), "mine");  // the request field wins
  EXPECT_FALSE(colmapAvailable());
  unsetenv("PLUVIA_COLMAP");
  EXPECT_EQ(colmapProgram(), "colmap");
}

TEST(SfmColmap, LundStreetRegistersWithSmallError) {
  std::filesystem::path data = test::sharedData();
  if (data.empty() || !std::filesystem::exists(data / "sfm" / "opensfm_lund" / "01.jpg"))
    GTEST_SKIP() << "../shared/data/sfm/opensfm_lund is absent";
  if (!colmapAvailable()) GTEST_SKIP() << "colmap is not installed";
  auto dir = test::freshTempDir("sfm_colmap_lund");
  std::filesystem::create_directories(dir / "frames");
  ColmapRequest request;
  std::map<std::string, int64_t> frames;
  for (int i = 1; i <= 12; ++i) {
    char name[16];
    std::snprintf(name, sizeof name, "%02d.jpg", i);
    cv::Mat full = cv::imread((data / "sfm" / "opensfm_lund" / name).string());
    ASSERT_FALSE(full.empty()) << name;
    cv::Mat small;
    cv::resize(full, small, cv::Size(800, full.rows * 800 / full.cols), 0, 0, cv::INTER_AREA);
    std::string out = "frame." + std::to_string(1000 + i) + ".png";
    cv::imwrite((dir / "frames" / out).string(), small);
    request.images.push_back(dir / "frames" / out);
    frames[out] = 1000 + i;
  }
  request.workspace = dir / "colmap";
  request.maxImageSizePx = 800;
  request.threads = 1;
  // These are photos several metres apart, not video: frames 4+ apart share few features, and
  // matching them lets the mapper start from a weak, distant pair.
  request.sequentialOverlap = 3;
  // The phone's field of view is about 75 deg (focal ~0.65 of the width); COLMAP's own guess
  // (1.2 x width) is so far off that registration stalls after the first pair.
  request.initialFocalPx = 0.65 * 800;
  auto start = std::chrono::steady_clock::now();
  ColmapRun run = runColmapSparse(request);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ColmapModel model = readColmapTextModel(run.modelFolder);
  SfmOptions options;
  options.scale.cameraHeightMeters = 1.6;
  SfmReconstruction r = reconstructionFromColmap(model, frames, options);
  std::printf(
      "lund: %d/%d registered (%.2f), reprojection %.3f px, baseline/depth %.3f, "
      "focal %.1f px, status '%s', %.1f s\n",
      r.registeredCount, r.frameCount, r.registeredFraction, r.meanReprojectionErrorPx,
      r.baselineOverDepth, r.intrinsics.focalPx, r.message.c_str(), seconds);
  EXPECT_GE(r.registeredFraction, 0.8);
  EXPECT_GT(model.points.size(), 300u);
  EXPECT_GT(r.meanReprojectionErrorPx, 0.05);  // a real residual, not an empty model
  EXPECT_LT(r.meanReprojectionErrorPx, 1.5);
  // A walk, not a pan.
  EXPECT_GT(r.baselineOverDepth, 0.05);
  EXPECT_NE(r.status, SfmStatus::NoParallax);
  EXPECT_NE(r.status, SfmStatus::TooFewRegistered);
  // The walk goes forward: the last registered camera is ahead of the first along its view.
  if (r.keyframes.size() >= 2) {
    const Camera& a = r.keyframes.front().camera;
    const Camera& b = r.keyframes.back().camera;
    Eigen::Vector3d forward = a.worldFromCamera * Eigen::Vector3d(0, 0, -1);
    EXPECT_GT(forward.dot(b.positionMeters - a.positionMeters),
              0.5 * (b.positionMeters - a.positionMeters).norm());
  }
  // Densify the first keyframe: its samples come out finite and positive.
  if (!r.keyframes.empty()) {
    const SfmKeyframe& k = r.keyframes.front();
    cv::Mat guide = cv::imread((dir / "frames" / k.imageName).string());
    auto samples = projectSparsePoints(k.camera, r.pointsMeters, &k.visiblePoints);
    std::vector<float> depth = densifySparseDepth(samples, guide);
    int finite = 0, skyTop = 0;
    for (float d : depth) finite += std::isfinite(d) && d > 0;
    for (int x = 0; x < guide.cols; ++x) skyTop += std::isinf(depth[5 * guide.cols + x]);
    std::printf("lund densify: %zu samples, %.2f finite, %.2f of row 5 is sky\n", samples.size(),
                finite / double(depth.size()), skyTop / double(guide.cols));
    EXPECT_GT(finite, static_cast<int>(depth.size() / 3));
    // The top of these frames is blue sky: most of row 5 must stay +inf (measured 0.91).
    EXPECT_GT(skyTop, guide.cols / 2);
  }
}
