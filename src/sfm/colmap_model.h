#pragma once
// COLMAP's text model (cameras.txt, images.txt, points3D.txt) as plain structs, in COLMAP's own
// convention: an image's pose (qvec, tvec) maps world points into its camera frame
// (x_cam = R(qvec) * x_world + tvec), the camera looks along +Z with +Y down, and pixel centres
// sit at +0.5 like pluvia's. Units are the model's arbitrary scale; sfm_poses.h turns them into
// pluvia's metric world.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace pluvia::sfm {

struct ColmapCamera {
  int id = 0;
  std::string model;  // "SIMPLE_RADIAL", "PINHOLE", ...
  int width = 0;
  int height = 0;
  std::vector<double> params;  // in COLMAP's order for the model

  // Focal length (the mean of fx and fy for two-focal models) and principal point, in pixels.
  // Throws pluvia::Error for a model this reader does not know.
  double focalPx() const;
  double cxPx() const;
  double cyPx() const;
};

struct ColmapObservation {
  Eigen::Vector2d xyPx = Eigen::Vector2d::Zero();
  int64_t point3DId = -1;  // -1: a keypoint with no triangulated point
};

struct ColmapImage {
  int id = 0;
  Eigen::Quaterniond qvec = Eigen::Quaterniond::Identity();  // camera from world (w, x, y, z)
  Eigen::Vector3d tvec = Eigen::Vector3d::Zero();
  int cameraId = 0;
  std::string name;  // file name relative to the image folder
  std::vector<ColmapObservation> observations;

  Eigen::Matrix3d cameraFromWorld() const { return qvec.normalized().toRotationMatrix(); }
  // The camera centre in model coordinates: -R^T t.
  Eigen::Vector3d centre() const { return -cameraFromWorld().transpose() * tvec; }
};

struct ColmapTrackElement {
  int imageId = 0;
  int point2DIndex = 0;
};

struct ColmapPoint3D {
  int64_t id = 0;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  Eigen::Vector3i rgb = Eigen::Vector3i::Zero();
  double errorPx = 0.0;  // mean reprojection error over the track
  std::vector<ColmapTrackElement> track;
};

struct ColmapModel {
  std::map<int, ColmapCamera> cameras;
  std::map<int, ColmapImage> images;  // registered images only
  std::unordered_map<int64_t, ColmapPoint3D> points;

  // Mean of the points' reprojection errors weighted by track length (COLMAP's own figure);
  // 0 for a model without points.
  double meanReprojectionErrorPx() const;
};

// Each parser reads one file's text; `fileName` is used only in error messages, which name the
// file and the line. They throw pluvia::Error on malformed input.
void parseColmapCameras(const std::string& text, const std::string& fileName, ColmapModel& model);
void parseColmapImages(const std::string& text, const std::string& fileName, ColmapModel& model);
void parseColmapPoints3D(const std::string& text, const std::string& fileName, ColmapModel& model);

// Reads cameras.txt, images.txt and points3D.txt from `folder` (model_converter's TXT output).
ColmapModel readColmapTextModel(const std::filesystem::path& folder);

}  // namespace pluvia::sfm
