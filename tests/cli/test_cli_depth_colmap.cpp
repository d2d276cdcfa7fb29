// The depth stage's COLMAP source in a render: clips of the synthetic street
// (lab/synthetic_scene.h) written as PNG sequences, tracked by the real colmap. A walk tracks,
// renders with the tracked camera, caches its tracking (plan: needed, then cached) and reuses it; a
// colmap that cannot run (naming its log) and a tripod pan (no parallax, found before COLMAP runs)
// stop the render before any frame, unless depth.fallback = layers, which renders with the manual
// layers and says why. A model given by depth.colmap_model (the walk's true one) is read without
// COLMAP, and a dense map replaces its densified points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "lab/synthetic_scene.h"
#include "sfm/colmap_runner.h"
#include "sfm/dense_import.h"
#include "test_support.h"
#include "util/fs.h"

using namespace pluvia::sfm;

namespace pluvia {
namespace {

namespace stdfs = std::filesystem;

// 720p: at 320x180 and 640x360 COLMAP settles on a wrong solution for this ground-dominated walk
// (pluvia report depth), which the depth stage then refuses (no ground plane below the cameras).
constexpr int kWidth = 1280;
constexpr int kHeight = 720;
constexpr int kFrames = 12;

size_t countFiles(const stdfs::path& dir, const std::string& extension) {
  size_t n = 0;
  for (const auto& entry : stdfs::directory_iterator(dir))
    n += entry.path().extension() == extension ? 1 : 0;
  return n;
}

// Writes frames 1..kFrames of `keys` as dir/street.####.png; returns the sequence pattern. The
// true z-depth of frame N is appended to `trueDepth` (index N - 1) when given.
std::string writeClip(const stdfs::path& dir, const std::vector<lab::SyntheticPathKey>& keys,
                      std::vector<std::vector<float>>* trueDepth = nullptr) {
  lab::SyntheticSceneRenderer renderer(kWidth, kHeight);
  const lab::SyntheticView intrinsics = lab::defaultSyntheticIntrinsics(kWidth, kHeight);
  for (int i = 0; i < kFrames; ++i) {
    Image frame = renderer.render(lab::syntheticViewAt(intrinsics, keys[size_t(i)]));
    test::writeImageFile(dir / fmt::format("street.{:04d}.png", i + 1), frame);
    if (trueDepth) trueDepth->push_back(*frame.findPlane("depth"));
  }
  return (dir / "street.####.png").string();
}

// The clip's true cameras and surface points as a COLMAP text model in metres (what COLMAP would
// reconstruct, without its noise or its run time): a PINHOLE camera, each frame an image
// frame_%08d.png posed camera-from-world in COLMAP's axes (+Z forward, +Y down), and points
// back-projected from every frame's true depth on a 32 px grid, each tracked in the frames that
// see it unoccluded (the point's depth there within 0.5 % of that frame's true depth).
void writeTrueModel(const stdfs::path& folder, const std::vector<lab::SyntheticPathKey>& keys,
                    const std::vector<std::vector<float>>& trueDepth) {
  const lab::SyntheticView intrinsics = lab::defaultSyntheticIntrinsics(kWidth, kHeight);
  struct Pose {
    Eigen::Matrix3d worldFromCamera;  // pluvia's camera axes: +Y up, looking along -Z
    Eigen::Vector3d centre;
  };
  std::vector<Pose> poses;
  for (const auto& key : keys) {
    const lab::SyntheticView view = lab::syntheticViewAt(intrinsics, key);
    Pose pose;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        pose.worldFromCamera(r, c) = view.worldFromCamera[size_t(3 * r + c)];
      pose.centre[r] = view.positionMeters[size_t(r)];
    }
    poses.push_back(pose);
  }
  const Eigen::Matrix3d colmapFromPluvia = Eigen::Vector3d(1, -1, -1).asDiagonal();
  const double f = intrinsics.focalPx, cx = intrinsics.cx, cy = intrinsics.cy;
  struct Observation {
    int image;
    Eigen::Vector2d xy;
    int64_t point;
  };
  std::vector<std::vector<Observation>> observed(poses.size());
  std::vector<Eigen::Vector3d> points;
  constexpr int kGridPx = 32;
  for (size_t i = 0; i < poses.size(); ++i) {
    for (int y = kGridPx / 2; y < kHeight; y += kGridPx) {
      for (int x = kGridPx / 2; x < kWidth; x += kGridPx) {
        const float z = trueDepth[i][size_t(y) * kWidth + x];
        if (!std::isfinite(z)) continue;
        const Eigen::Vector3d ray((x + 0.5 - cx) / f, -(y + 0.5 - cy) / f, -1.0);
        const Eigen::Vector3d world = poses[i].centre + poses[i].worldFromCamera * (ray * z);
        const int64_t id = int64_t(points.size()) + 1;
        points.push_back(world);
        for (size_t j = 0; j < poses.size(); ++j) {
          const Eigen::Vector3d c =
              colmapFromPluvia * poses[j].worldFromCamera.transpose() * (world - poses[j].centre);
          if (c.z() <= 0.0) continue;
          const Eigen::Vector2d xy(cx + f * c.x() / c.z(), cy + f * c.y() / c.z());
          if (xy.x() < 0 || xy.y() < 0 || xy.x() >= kWidth || xy.y() >= kHeight) continue;
          const float there = trueDepth[j][size_t(xy.y()) * kWidth + size_t(xy.x())];
          if (!(std::abs(there - c.z()) < 0.005 * c.z())) continue;
          observed[j].push_back({int(j) + 1, xy, id});
        }
      }
    }
  }
  stdfs::create_directories(folder);
  std::ofstream(folder / "cameras.txt")
      << fmt::format("1 PINHOLE {} {} {} {} {} {}\n", kWidth, kHeight, f, f, cx, cy);
  std::ofstream images(folder / "images.txt");
  std::vector<std::string> tracks(points.size());
  for (size_t j = 0; j < poses.size(); ++j) {
    const Eigen::Matrix3d cameraFromWorld = colmapFromPluvia * poses[j].worldFromCamera.transpose();
    const Eigen::Quaterniond q(cameraFromWorld);
    const Eigen::Vector3d t = -cameraFromWorld * poses[j].centre;
    images << fmt::format("{} {} {} {} {} {} {} {} 1 frame_{:08d}.png\n", j + 1, q.w(), q.x(),
                          q.y(), q.z(), t.x(), t.y(), t.z(), j + 1);
    for (size_t k = 0; k < observed[j].size(); ++k) {
      const Observation& o = observed[j][k];
      images << fmt::format("{}{} {} {}", k ? " " : "", o.xy.x(), o.xy.y(), o.point);
      tracks[size_t(o.point - 1)] += fmt::format(" {} {}", o.image, k);
    }
    images << "\n";
  }
  std::ofstream points3D(folder / "points3D.txt");
  for (size_t i = 0; i < points.size(); ++i)
    if (!tracks[i].empty())
      points3D << fmt::format("{} {} {} {} 128 128 128 0.1{}\n", i + 1, points[i].x(),
                              points[i].y(), points[i].z(), tracks[i]);
}

// A walk: every 4th key of the default 48-frame path (0.2 m a frame down the street).
std::vector<lab::SyntheticPathKey> walk() {
  const auto path = lab::defaultSyntheticPath(48);
  std::vector<lab::SyntheticPathKey> keys;
  for (int i = 0; i < kFrames; ++i) keys.push_back(path[size_t(4 * i)]);
  return keys;
}

// A tripod pan: the first key's position, yaw from -6 to +5 degrees.
std::vector<lab::SyntheticPathKey> pan() {
  std::vector<lab::SyntheticPathKey> keys(kFrames, lab::defaultSyntheticPath(1)[0]);
  for (int i = 0; i < kFrames; ++i) keys[size_t(i)].yawDeg = -6.0 + i;
  return keys;
}

std::vector<std::string> renderArgs(const std::string& clip, const stdfs::path& out,
                                    const std::vector<std::string>& sets) {
  std::vector<std::string> args{"render", clip,   "-o",    (out / "wet.####.png").string(),
                                "-p",     "base", "--set", "depth.source=colmap"};
  for (const std::string& set : sets) args.insert(args.end(), {"--set", set});
  return args;
}

class CliDepthColmap : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!colmapAvailable()) GTEST_SKIP() << "colmap is not installed";
  }
};

TEST_F(CliDepthColmap, TrackedWalkRendersCachesAndReusesItsTracking) {
  const stdfs::path dir = test::freshTempDir("depth_colmap_walk");
  const std::string clip = writeClip(dir, walk());
  const stdfs::path cache = dir / "cache", out = dir / "out";
  stdfs::create_directories(out);
  const std::vector<std::string> sets{"camera.fov_deg=60", "camera.height_m=1.6"};
  std::vector<std::string> plan{"plan",    clip,           "-p",    "base",
                                "--cache", cache.string(), "--set", "depth.source=colmap"};
  for (const std::string& set : sets) plan.insert(plan.end(), {"--set", set});

  auto before = test::runPluvia(plan);
  ASSERT_EQ(before.exitCode, 0) << before.output;
  EXPECT_NE(before.output.find("per-clip analysis needed (not in the cache)"), std::string::npos)
      << before.output;

  // COLMAP tracks the whole clip whatever frames are rendered: two show it (the suite's time).
  std::vector<std::string> render = renderArgs(clip, out, sets);
  render.insert(render.end(), {"--cache", cache.string(), "--frames", "1-2"});
  auto first = test::runPluvia(render);
  ASSERT_EQ(first.exitCode, 0) << first.output;
  EXPECT_NE(first.output.find(fmt::format("COLMAP registered {} of {} frames", kFrames, kFrames)),
            std::string::npos)
      << first.output;
  EXPECT_NE(first.output.find("rain: camera tracked by COLMAP"), std::string::npos) << first.output;
  EXPECT_EQ(countFiles(out, ".png"), size_t(2));
  // The workspace (frames, database) is removed once the tracking is in the cache.
  for (const auto& entry : stdfs::directory_iterator(cache))
    EXPECT_FALSE(entry.is_directory()) << entry.path();

  auto after = test::runPluvia(plan);
  ASSERT_EQ(after.exitCode, 0) << after.output;
  EXPECT_NE(after.output.find("per-clip analysis cached"), std::string::npos) << after.output;

  stdfs::remove_all(out);
  stdfs::create_directories(out);
  auto second = test::runPluvia(render);
  ASSERT_EQ(second.exitCode, 0) << second.output;
  EXPECT_NE(second.output.find("COLMAP tracking from cache"), std::string::npos) << second.output;
  EXPECT_EQ(second.output.find("COLMAP registered"), std::string::npos) << second.output;
  EXPECT_EQ(countFiles(out, ".png"), size_t(2));
}

TEST_F(CliDepthColmap, MissingColmapStopsBeforeAnyFrameUnlessFallbackAllowsLayers) {
  const stdfs::path dir = test::freshTempDir("depth_colmap_missing_render");
  const std::string clip = writeClip(dir, walk());
  const stdfs::path out = dir / "out";
  stdfs::create_directories(out);
  ::setenv("PLUVIA_COLMAP", "/nonexistent/colmap", 1);
  auto refused = test::runPluvia(renderArgs(clip, out, {}));
  auto fallback = test::runPluvia(renderArgs(clip, out, {"depth.fallback=layers"}));
  stdfs::create_directories(dir / "z");
  auto depth =
      test::runPluvia({"depth", clip, "-o", (dir / "z/z.####.exr").string(), "--source", "colmap"});
  ::unsetenv("PLUVIA_COLMAP");

  // pluvia depth names the step that failed and the log, which it keeps; no depth is written.
  EXPECT_EQ(depth.exitCode, 1) << depth.output;
  EXPECT_NE(depth.output.find("feature_extractor"), std::string::npos) << depth.output;
  EXPECT_NE(depth.output.find((dir / "z/colmap/colmap.log").string()), std::string::npos)
      << depth.output;
  EXPECT_TRUE(stdfs::exists(dir / "z/colmap/colmap.log"));
  EXPECT_EQ(countFiles(dir / "z", ".exr"), 0u);

  EXPECT_EQ(refused.exitCode, 1) << refused.output;
  EXPECT_NE(refused.output.find("colmap.log"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("depth.fallback"), std::string::npos) << refused.output;
  ASSERT_EQ(fallback.exitCode, 0) << fallback.output;
  EXPECT_NE(fallback.output.find("using the manual depth layers"), std::string::npos)
      << fallback.output;
  EXPECT_EQ(countFiles(out, ".png"), size_t(kFrames));  // all from the fallback run
}

TEST_F(CliDepthColmap, TripodPanIsRefusedAsNoParallaxOrFallsBackToLayers) {
  const stdfs::path dir = test::freshTempDir("depth_colmap_pan");
  const std::string clip = writeClip(dir, pan());
  const stdfs::path out = dir / "out";
  stdfs::create_directories(out);
  auto refused = test::runPluvia(renderArgs(clip, out, {}));
  EXPECT_EQ(refused.exitCode, 1) << refused.output;
  EXPECT_NE(refused.output.find("pan or a tripod"), std::string::npos) << refused.output;
  EXPECT_EQ(countFiles(out, ".png"), 0u);

  auto fallback = test::runPluvia(renderArgs(clip, out, {"depth.fallback=layers"}));
  ASSERT_EQ(fallback.exitCode, 0) << fallback.output;
  EXPECT_NE(fallback.output.find("pan or a tripod"), std::string::npos) << fallback.output;
  EXPECT_EQ(countFiles(out, ".png"), size_t(kFrames));
}

TEST_F(CliDepthColmap, GivenModelIsReadAndDenseMapsReplaceTheDensifiedPoints) {
  // A model given by depth.colmap_model is read, and COLMAP never runs: here the walk's true
  // cameras and points (writeTrueModel). A first run densifies its points; a second imports a
  // dense depth map for frame 5 in COLMAP's format (the true depth in model units, its left
  // half a hole): the right half must come back as the truth at the model's metric scale, the
  // hole as the first run's densified depth.
  const stdfs::path dir = test::freshTempDir("depth_colmap_model");
  std::vector<std::vector<float>> truth;
  const std::string clip = writeClip(dir, walk(), &truth);
  writeTrueModel(dir / "model", walk(), truth);
  stdfs::create_directories(dir / "z1");
  stdfs::create_directories(dir / "z2");
  const std::vector<std::string> sets{"--set", "camera.fov_deg=60",
                                      "--set", "camera.height_m=1.6",
                                      "--set", "depth.colmap_model=" + (dir / "model").string()};
  const int frame = 5;
  ColmapArray map{kWidth, kHeight, 1, {}};
  for (size_t i = 0; i < truth[frame - 1].size(); ++i) {
    const float z = truth[frame - 1][i];
    const bool hole = int(i % kWidth) < kWidth / 2 || !std::isfinite(z);
    map.values.push_back(hole ? 0.0f : z);
  }
  const stdfs::path dense = dir / "dense";
  stdfs::create_directories(dense / "stereo/depth_maps");
  writeColmapArray(colmapDepthMapPath(dense, fmt::format("frame_{:08d}.png", frame)), map);

  std::vector<std::string> first{"depth",    clip,    "-o", (dir / "z1/z.####.exr").string(),
                                 "--source", "colmap"};
  first.insert(first.end(), sets.begin(), sets.end());
  std::vector<std::string> second{
      "depth",    clip,     "-o",    (dir / "z2/z.####.exr").string(),
      "--source", "colmap", "--set", "depth.colmap_dense=" + dense.string()};
  second.insert(second.end(), sets.begin(), sets.end());
  ::setenv("PLUVIA_COLMAP", "/nonexistent/colmap", 1);  // proves that COLMAP does not run
  auto densified = test::runPluvia(first);
  auto imported = test::runPluvia(second);
  ::unsetenv("PLUVIA_COLMAP");
  ASSERT_EQ(densified.exitCode, 0) << densified.output;
  ASSERT_EQ(imported.exitCode, 0) << imported.output;
  EXPECT_NE(imported.output.find(fmt::format("{} of {} frames registered", kFrames, kFrames)),
            std::string::npos)
      << imported.output;

  const Image before = test::readImageFile(dir / "z1/z.0005.exr");
  const Image result = test::readImageFile(dir / "z2/z.0005.exr");
  // The metric scale pluvia found for the model (from the camera height over its ground): one
  // number for the whole map, and near 1 since the model is in metres.
  std::vector<double> ratios;
  for (size_t i = 0; i < map.values.size(); ++i)
    if (map.values[i] > 0) ratios.push_back(result.rgba[4 * i] / map.values[i]);
  ASSERT_GT(ratios.size(), size_t(kWidth * kHeight / 4));
  std::nth_element(ratios.begin(), ratios.begin() + ratios.size() / 2, ratios.end());
  const double metersPerUnit = ratios[ratios.size() / 2];
  EXPECT_NEAR(metersPerUnit, 1.0, 0.02);
  int checked = 0;
  for (size_t i = 0; i < truth[frame - 1].size(); ++i) {
    const float z = result.rgba[4 * i], z1 = before.rgba[4 * i];
    const double expected = map.values[i] > 0 ? metersPerUnit * map.values[i] : z1;
    if (!std::isfinite(expected)) {
      EXPECT_EQ(z, expected) << "pixel " << i;
      continue;
    }
    ASSERT_NEAR(z, expected, 1e-4 * expected) << "pixel " << i;
    ++checked;
  }
  EXPECT_GT(checked, kWidth * kHeight / 2);
  // Frames without a dense map keep the densified points exactly.
  const Image other1 = test::readImageFile(dir / "z1/z.0006.exr");
  const Image other2 = test::readImageFile(dir / "z2/z.0006.exr");
  EXPECT_EQ(other1.rgba, other2.rgba);
}

}  // namespace
}  // namespace pluvia
