// COLMAP file formats: the text model reader and the dense depth-map (.bin) reader.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "sfm/colmap_model.h"
#include "sfm/dense_import.h"
#include "test_support.h"
#include "util/error.h"

using namespace pluvia;
using namespace pluvia::sfm;
using pluvia::test::expectError;
using pluvia::test::expectOutputHas;

namespace {

// A model as model_converter writes it (comment header, one camera, two images, two points);
// the second image has an empty observation line.
const char* kCameras =
    "# Camera list with one line of data per camera:\n"
    "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
    "1 SIMPLE_RADIAL 800 600 519.85 400 300 -0.0627\n";
const char* kImages =
    "# Image list with two lines of data per image:\n"
    "10 0.7071067811865476 0 0.7071067811865476 0 1 2 3 1 10.jpg\n"
    "100.5 200.25 7 300 400 -1\n"
    "11 1 0 0 0 0 0 0 1 11.jpg\n"
    "\n";
const char* kPoints =
    "# 3D point list\n"
    "7 0.5 -1.5 2.5 38 48 20 0.6 10 0 11 4\n"
    "8 1 2 3 1 2 3 1.2 10 1\n";

ColmapModel parseAll() {
  ColmapModel model;
  parseColmapCameras(kCameras, "cameras.txt", model);
  parseColmapImages(kImages, "images.txt", model);
  parseColmapPoints3D(kPoints, "points3D.txt", model);
  return model;
}

}  // namespace

TEST(ColmapModel, ReadsCameras) {
  ColmapModel model = parseAll();
  ASSERT_EQ(model.cameras.size(), 1u);
  const ColmapCamera& c = model.cameras.at(1);
  EXPECT_EQ(c.model, "SIMPLE_RADIAL");
  EXPECT_EQ(c.width, 800);
  EXPECT_EQ(c.height, 600);
  EXPECT_DOUBLE_EQ(c.focalPx(), 519.85);
  EXPECT_DOUBLE_EQ(c.cxPx(), 400.0);
  EXPECT_DOUBLE_EQ(c.cyPx(), 300.0);
  EXPECT_DOUBLE_EQ(c.params[3], -0.0627);
}

TEST(ColmapModel, PinholeFocalIsTheMeanOfFxFy) {
  ColmapModel model;
  parseColmapCameras("2 PINHOLE 640 480 500 510 320.5 240.5\n", "cameras.txt", model);
  EXPECT_DOUBLE_EQ(model.cameras.at(2).focalPx(), 505.0);
  EXPECT_DOUBLE_EQ(model.cameras.at(2).cxPx(), 320.5);
  EXPECT_DOUBLE_EQ(model.cameras.at(2).cyPx(), 240.5);
}

TEST(ColmapModel, ReadsImagesAndObservations) {
  ColmapModel model = parseAll();
  ASSERT_EQ(model.images.size(), 2u);
  const ColmapImage& a = model.images.at(10);
  EXPECT_EQ(a.name, "10.jpg");
  EXPECT_EQ(a.cameraId, 1);
  EXPECT_NEAR(a.qvec.w(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(a.qvec.y(), std::sqrt(0.5), 1e-15);
  EXPECT_EQ(a.tvec, Eigen::Vector3d(1, 2, 3));
  ASSERT_EQ(a.observations.size(), 2u);
  EXPECT_EQ(a.observations[0].xyPx, Eigen::Vector2d(100.5, 200.25));
  EXPECT_EQ(a.observations[0].point3DId, 7);
  EXPECT_EQ(a.observations[1].point3DId, -1);
  // (w, y) = (sqrt 0.5, sqrt 0.5) is 90 deg about +Y; the centre is -R^T t.
  Eigen::Matrix3d r = a.cameraFromWorld();
  EXPECT_TRUE(
      r.isApprox(Eigen::Matrix3d(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY())), 1e-12));
  EXPECT_TRUE(a.centre().isApprox(-r.transpose() * Eigen::Vector3d(1, 2, 3), 1e-12));
  EXPECT_TRUE(model.images.at(11).observations.empty());
}

TEST(ColmapModel, ReadsPointsAndTracks) {
  ColmapModel model = parseAll();
  ASSERT_EQ(model.points.size(), 2u);
  const ColmapPoint3D& p = model.points.at(7);
  EXPECT_EQ(p.xyz, Eigen::Vector3d(0.5, -1.5, 2.5));
  EXPECT_EQ(p.rgb, Eigen::Vector3i(38, 48, 20));
  EXPECT_DOUBLE_EQ(p.errorPx, 0.6);
  ASSERT_EQ(p.track.size(), 2u);
  EXPECT_EQ(p.track[1].imageId, 11);
  EXPECT_EQ(p.track[1].point2DIndex, 4);
  // Track-length weighted: (0.6 * 2 + 1.2 * 1) / 3.
  EXPECT_NEAR(model.meanReprojectionErrorPx(), 0.8, 1e-12);
}

TEST(ColmapModel, MalformedInputNamesFileAndLine) {
  // Each case: the reader, the file it stands for, its text and what the error must name.
  struct Malformed {
    void (*parse)(const std::string&, const std::string&, ColmapModel&);
    const char* file;
    const char* text;
    std::vector<std::string> named;
  };
  const std::vector<Malformed> cases{
      {parseColmapCameras,
       "cameras.txt",
       "# c\n1 PINHOLE 640 480 500 510 320\n",
       {"cameras.txt line 2", "4 parameters"}},
      {parseColmapCameras, "cameras.txt", "1 WEIRD 640 480 1\n", {"unknown camera model WEIRD"}},
      {parseColmapImages,
       "images.txt",
       "1 1 0 0 0 0 0 0 1 a.jpg\n1 2 x\n",
       {"images.txt line 2", "'x' is not a number"}},
      {parseColmapImages, "images.txt", "1 1 0 0 0 0 0 1 a.jpg\n\n", {"images.txt line 1"}},
      {parseColmapPoints3D,
       "points3D.txt",
       "# p\n\n5 1 2 3 0 0 0 0.5 1\n",
       {"points3D.txt line 3"}}};
  ColmapModel model;
  for (const Malformed& c : cases) {
    const Error e = expectError([&] { c.parse(c.text, c.file, model); }, c.named[0]);
    expectOutputHas(e.what(), c.named);
  }
}

TEST(ColmapModel, MissingFileIsNamed) {
  auto dir = test::freshTempDir("colmap_model_missing");
  std::ofstream(dir / "cameras.txt") << kCameras;
  expectError([&] { readColmapTextModel(dir); }, (dir / "images.txt").string());
}

TEST(ColmapDenseImport, RoundTripAndLayout) {
  auto dir = test::freshTempDir("colmap_dense");
  ColmapArray a;
  a.width = 3;
  a.height = 2;
  a.channels = 1;
  a.values = {1, 2, 0, 4, 5, 6};  // row-major: row 0 = 1 2 0, row 1 = 4 5 6
  auto path = colmapDepthMapPath(dir, "f.jpg");
  EXPECT_EQ(path, dir / "stereo" / "depth_maps" / "f.jpg.geometric.bin");
  std::filesystem::create_directories(path.parent_path());
  writeColmapArray(path, a);
  // The header is ASCII "3&2&1&" and the data follows directly: 6 + 6 * 4 bytes.
  EXPECT_EQ(std::filesystem::file_size(path), 6u + 24u);
  ColmapArray b = readColmapArray(path);
  EXPECT_EQ(b.width, 3);
  EXPECT_EQ(b.height, 2);
  EXPECT_EQ(b.values, a.values);
  int w = 0, h = 0;
  std::vector<float> depth = importColmapDepthMeters(path, 2.5, &w, &h);
  EXPECT_EQ(w, 3);
  EXPECT_EQ(h, 2);
  EXPECT_FLOAT_EQ(depth[1], 5.0f);    // row 0, col 1
  EXPECT_FLOAT_EQ(depth[3], 10.0f);   // row 1, col 0
  EXPECT_TRUE(std::isnan(depth[2]));  // 0 = no estimate
}

TEST(ColmapDenseImport, TruncatedFileIsNamed) {
  auto dir = test::freshTempDir("colmap_dense_bad");
  auto path = dir / "x.bin";
  std::ofstream(path, std::ios::binary) << "4&4&1&abcd";
  const Error truncated = expectError([&] { readColmapArray(path); }, path.string());
  expectOutputHas(truncated.what(), {"data ends after 4 of 64 bytes"});
  std::ofstream(path, std::ios::binary) << "4x4&1&";
  expectError([&] { readColmapArray(path); }, "bad header");
}
