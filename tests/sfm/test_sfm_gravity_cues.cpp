// The ground below the cameras (its tilt along the path from the cameras' steady height) and the
// scale cues' warnings, on synthetic layouts whose answers are known.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "sfm/clip_tracking.h"
#include "sfm/ground_plane.h"
#include "sfm/scale_cues.h"
#include "sfm/sfm_poses.h"
#include "test_support.h"

using namespace pluvia;
using namespace pluvia::sfm;

namespace {

double degreesBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace

// A street rising 2 deg along the walk (-Z): its points cover only the first 6 m, with 3 cm of
// noise (cobbles); twelve cameras ride 1.6 m above it over 50 m. A level awning 0.4 m above the
// first camera, denser than the street, is not the ground: the first camera stands below it.
TEST(GroundBelowCameras, FindsTheStreetBelowEveryCamera) {
  const double slope = 2.0 * M_PI / 180.0;
  const Eigen::Vector3d n(0.0, std::cos(slope), std::sin(slope));
  const Eigen::Vector3d forward(0.0, std::sin(slope), -std::cos(slope));  // in the street
  const Eigen::Vector3d across = Eigen::Vector3d::UnitX();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> cobble(0.0, 0.03);
  std::vector<Eigen::Vector3d> points, cameras;
  for (int i = 0; i < 300; ++i)
    points.push_back((u(rng) - 0.5) * 6.0 * across + 6.0 * u(rng) * forward + cobble(rng) * n);
  for (int k = 0; k < 12; ++k) cameras.push_back(50.0 * k / 11.0 * forward + 1.6 * n);
  for (int i = 0; i < 500; ++i)
    points.push_back({(u(rng) - 0.5) * 4.0, cameras.front().y() + 0.4, -8.0 * u(rng)});
  PlaneFitOptions options;
  options.inlierDistance = 0.1;
  const PlaneFit alone = fitGroundPlane(points, Eigen::Vector3d::UnitY(), options);
  const GroundBelowCameras fit =
      fitGroundBelowCameras(points, cameras, Eigen::Vector3d::UnitY(), options);
  ASSERT_TRUE(fit.plane.found);
  EXPECT_TRUE(fit.camerasUsed);
  std::printf("points alone: %.2f deg from the street (%d inliers); below the cameras %.3f deg\n",
              degreesBetween(alone.normal, n), alone.inliers, degreesBetween(fit.plane.normal, n));
  EXPECT_GT(degreesBetween(alone.normal, n), 1.5);  // the awning
  EXPECT_LT(degreesBetween(fit.plane.normal, n), 0.2);
  // Along the path the cameras fix the tilt: every height within 1 cm over the 50 m.
  for (const Eigen::Vector3d& c : cameras)
    EXPECT_NEAR(fit.plane.normal.dot(c) + fit.plane.offset, 1.6, 0.01);
}

// Sceaux Castle's layout: the only ground points lie at the façade's foot, 50 to 90 m from a
// walk of eleven photos on an arc over level ground; the inlier band, 2 % of that depth, is
// 1.5 m, more than the first photo's height (taken lower, at 1.25 m; the others at 1.6 m). The
// joint plane passes under every camera, so it is used, and the heights are the cameras' own.
// Before, the joint plane had to pass the band under every camera too, and the points' own
// plane was kept: on Sceaux, 0.9 deg off the façades' vertical, heights from 1.30 to 1.78 m.
TEST(GroundBelowCameras, GroundPointsFarFromTheWalkAreJoinedByIt) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> gravel(0.0, 0.1);
  std::vector<Eigen::Vector3d> points, cameras;
  for (int i = 0; i < 300; ++i)
    points.push_back({(u(rng) - 0.5) * 60.0, gravel(rng), -50.0 - 40.0 * u(rng)});
  for (int k = 0; k < 11; ++k) {
    const double a = M_PI * (0.1 + 0.8 * k / 10.0);
    cameras.push_back({-40.0 * std::cos(a), k == 0 ? 1.25 : 1.6, -40.0 * std::sin(a) + 20.0});
  }
  PlaneFitOptions options;
  options.inlierDistance = 1.5;
  const GroundBelowCameras fit =
      fitGroundBelowCameras(points, cameras, Eigen::Vector3d::UnitY(), options);
  ASSERT_TRUE(fit.plane.found);
  EXPECT_TRUE(fit.camerasUsed);
  std::printf("far ground: points alone %.2f deg from the joint plane, which is %.3f deg off\n",
              fit.pointsOnlyTiltDeg, degreesBetween(fit.plane.normal, Eigen::Vector3d::UnitY()));
  // The cameras weigh as much as the points, so the first camera's dip tilts the joint plane by
  // about a tenth of a degree, 15 cm over the 80 m walk: the heights within 25 cm, the ten taken
  // at one height within 25 cm of each other.
  EXPECT_LT(degreesBetween(fit.plane.normal, Eigen::Vector3d::UnitY()), 0.25);
  double lo = 1e9, hi = -1e9;
  for (size_t k = 0; k < cameras.size(); ++k) {
    const double height = fit.plane.normal.dot(cameras[k]) + fit.plane.offset;
    EXPECT_NEAR(height, cameras[k].y(), 0.25) << k;
    if (k > 0) lo = std::min(lo, height), hi = std::max(hi, height);
  }
  EXPECT_LT(hi - lo, 0.25);
}

namespace {

SfmReconstruction walk(const std::vector<double>& heights, double stepMeters, int frameStep) {
  SfmReconstruction r;
  r.groundAtYZero = true;
  for (size_t k = 0; k < heights.size(); ++k) {
    SfmKeyframe key;
    key.frame = 1001 + frameStep * static_cast<int64_t>(k);
    key.camera.positionMeters = {0.0, heights[k], -stepMeters * static_cast<double>(k)};
    key.heightAboveGroundMeters = heights[k];
    r.keyframes.push_back(key);
  }
  for (int i = 0; i < 100; ++i) r.pointsMeters.push_back({1.0, 0.08 * i, -5.0});  // 0 to 7.9 m
  return r;
}

bool mentions(const SfmReconstruction& r, const std::string& text) {
  for (const std::string& w : r.warnings)
    if (w.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(ScaleCues, ConsistentWalkHasNoWarning) {
  SfmReconstruction r = walk({1.58, 1.62, 1.6, 1.61}, 1.2, 25);
  r.verticalLineCount = 100;
  r.groundTiltFromVerticalDeg = 1.0;
  SfmOptions options;
  options.framesPerSecond = 25.0;
  checkScaleCues(r, options);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  EXPECT_NEAR(r.structureHeightMeters, 0.08 * 94, 1e-9);       // the 95th percentile of 0..7.92 m
  EXPECT_NEAR(r.medianCameraSpeedMetersPerSecond, 1.2, 1e-3);  // the heights' steps add a little
}

TEST(ScaleCues, EachDisagreeingCueWarnsWithItsNumbers) {
  // The château: cameras 0.89 to 1.96 m above the ground, buildings that come out no taller than
  // them, a camera crossing 30 m between frames 10 apart at 25 fps, a ground 9 deg off the lines.
  SfmReconstruction r = walk({0.89, 1.2, 1.96, 1.4}, 30.0, 10);
  for (Eigen::Vector3d& p : r.pointsMeters) p.y() *= 0.2;  // up to 1.6 m
  r.verticalLineCount = 240;
  r.groundTiltFromVerticalDeg = 9.0;
  SfmOptions options;
  options.framesPerSecond = 25.0;
  checkScaleCues(r, options);
  EXPECT_EQ(r.warnings.size(), 4u);
  EXPECT_TRUE(mentions(r, "from 0.89 to 1.96 m")) << r.warnings[0];
  EXPECT_TRUE(mentions(r, "tilts 9.0 deg from the vertical of 240 façade lines"));
  EXPECT_TRUE(mentions(r, "height above the ground is 1.50 m"));
  EXPECT_TRUE(mentions(r, "moves 75.0 m/s"));
}

// A bent model (the ground 10 deg off the façades, as COLMAP's two-thread mapper bent a street in
// 2 of 10 runs) is told by its bentness; a remap that came out straight replaces it, one that came
// out as bent or failed does not.
TEST(BentModel, IsDetectedAndAStraighterRemapReplacesIt) {
  SfmOptions options;
  SfmReconstruction bent = walk({1.58, 1.62, 1.6, 1.61}, 1.2, 25);
  bent.verticalLineCount = 120;
  bent.groundTiltFromVerticalDeg = 10.0;
  checkScaleCues(bent, options);
  std::string reason;
  EXPECT_NEAR(bentness(bent, options, &reason), 10.0 / 6.0, 1e-9);
  EXPECT_EQ(reason, "the ground tilts 10.0 deg from the façades' vertical");

  SfmReconstruction straight = walk({1.58, 1.62, 1.6, 1.61}, 1.2, 25);
  straight.verticalLineCount = 120;
  straight.groundTiltFromVerticalDeg = 1.5;
  checkScaleCues(straight, options);
  reason.clear();
  EXPECT_LT(bentness(straight, options, &reason), 1.0);
  EXPECT_TRUE(reason.empty());

  std::string why;
  EXPECT_TRUE(keepSecondModel(bent, straight, options, why));
  EXPECT_NE(why.find("kept the second model"), std::string::npos) << why;
  EXPECT_FALSE(keepSecondModel(bent, bent, options, why));
  SfmReconstruction failed = straight;
  failed.status = SfmStatus::NoGroundPlane;
  failed.message = "no ground plane below the cameras";
  EXPECT_FALSE(keepSecondModel(bent, failed, options, why));
  EXPECT_NE(why.find("no ground plane"), std::string::npos) << why;

  // Heights from 0.9 to 2.0 m (a standard deviation of 29 % of their mean) bend it too.
  SfmReconstruction spread = walk({0.9, 1.2, 2.0, 1.4}, 1.2, 25);
  checkScaleCues(spread, options);
  EXPECT_GT(bentness(spread, options, &reason), 1.0);
  EXPECT_NEAR(spread.cameraHeightSpread, 0.4023 / 1.375, 1e-3);
  EXPECT_NE(reason.find("camera heights' standard deviation is 29 %"), std::string::npos) << reason;
}

// After a remap, <workspace>/model holds the model kept: the first one when the remap was not
// straighter or built nothing (it once held the remap's model while the log said "kept the
// first", so depth.colmap_model read a model the render never used).
TEST(BentModel, TheWorkspaceKeepsTheFolderOfTheModelUsed) {
  const std::filesystem::path ws = test::freshTempDir("remap_model_folder");
  auto writeModel = [&](const std::string& which) {
    std::filesystem::create_directories(ws / "model");
    std::ofstream(ws / "model" / "images.txt") << which;
  };
  auto modelIs = [&]() {
    std::ifstream in(ws / "model" / "images.txt");
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  for (const bool remapped : {false, true}) {
    std::filesystem::remove_all(ws / "model");
    writeModel("first");
    setKeptModelAside(ws);
    EXPECT_FALSE(std::filesystem::exists(ws / "model"));
    writeModel("second");
    keepModelFolder(ws, remapped);
    EXPECT_EQ(modelIs(), remapped ? "second" : "first");
    EXPECT_FALSE(std::filesystem::exists(ws / "model.kept"));
  }
  // A remap that built no model wrote none: the first comes back.
  writeModel("first");
  setKeptModelAside(ws);
  keepModelFolder(ws, false);
  EXPECT_EQ(modelIs(), "first");
}

// A model still bent far past the bounds after the remap (a 29-photo walk came back from COLMAP
// with cameras from 139 m below the fitted ground to 21 m above it) is refused with the reason, so
// the render stops before its first frame instead of rendering with its scale; one bent within
// maxUsableBentness is used, with the warning.
TEST(BentModel, FarPastTheBoundsIsRefusedNotUsed) {
  SfmOptions options;
  SfmReconstruction broken = walk({-139.2, 1.6, 20.9, 3.0}, 1.2, 25);
  checkScaleCues(broken, options);
  refuseUnusableModel(broken, options);
  EXPECT_EQ(broken.status, SfmStatus::Bent);
  EXPECT_STREQ(sfmStatusName(broken.status), "bent");
  EXPECT_NE(broken.message.find("bent beyond use"), std::string::npos) << broken.message;
  EXPECT_NE(broken.message.find("camera heights' standard deviation"), std::string::npos)
      << broken.message;

  // Heights spreading 29 % (bentness 2.9) and a street 10 deg off the façades (1.7) stay usable.
  SfmReconstruction spread = walk({0.9, 1.2, 2.0, 1.4}, 1.2, 25);
  checkScaleCues(spread, options);
  refuseUnusableModel(spread, options);
  EXPECT_TRUE(spread.ok()) << spread.message;
  SfmReconstruction tilted = walk({1.58, 1.62, 1.6, 1.61}, 1.2, 25);
  tilted.verticalLineCount = 120;
  tilted.groundTiltFromVerticalDeg = 10.0;
  checkScaleCues(tilted, options);
  refuseUnusableModel(tilted, options);
  EXPECT_TRUE(tilted.ok()) << tilted.message;

  // A ground 20 deg off the façades' vertical is no ground the cameras walked on.
  tilted.groundTiltFromVerticalDeg = 20.0;
  refuseUnusableModel(tilted, options);
  EXPECT_EQ(tilted.status, SfmStatus::Bent);
  EXPECT_NE(tilted.message.find("tilts 20.0 deg"), std::string::npos) << tilted.message;
}
