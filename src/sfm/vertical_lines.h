#pragma once
// Gravity from the footage itself: the vertical vanishing point of buildings' edges (door and
// window frames, drainpipes, corners), found jointly over all registered images of a COLMAP
// model. SfM leaves "up" unknown, and the ground plane it is usually taken from can tilt (a
// sloping or cambered street, a reconstruction bent over a long walk); rain falls along gravity.
//
// Method: line segments (OpenCV's LSD) longer than minLengthFraction of the image diagonal are
// lifted to their interpretation planes (the plane through the camera centre and the segment,
// after undoing COLMAP's radial distortion), whose normals are rotated into model coordinates by
// the image's pose. A world-vertical segment's plane contains the vertical, so its normal n is
// perpendicular to up: n . up = 0. Segments whose plane is within candidateMaxDeg of containing
// the cameras' mean up are candidates; RANSAC over pairs (up = n_a x n_b) finds the direction
// most candidates' planes contain (inliers within inlierMaxDeg, scored by length), refined as the
// smallest eigenvector of the inliers' length-weighted sum of n n^T.
#include <filesystem>
#include <string>

#include <Eigen/Core>

#include "sfm/colmap_model.h"

namespace pluvia::sfm {

struct VerticalLineOptions {
  double minLengthFraction = 0.04;  // of the image diagonal
  // How far a candidate's plane may be from containing the cameras' mean up: people hold cameras
  // within a few degrees of level, and the mean up of COLMAP's cameras is no better than that.
  double candidateMaxDeg = 12.0;
  double inlierMaxDeg = 0.5;               // of a line's plane from containing the vertical
  double maxDeviationFromPriorDeg = 20.0;  // the answer's distance from the cameras' mean up
  int minInliers = 12;                     // lines, over all images
  int iterations = 2000;
  unsigned seed = 7;  // fixed: the same images give the same vertical
};

struct VerticalLineGravity {
  bool found = false;
  Eigen::Vector3d upModel = Eigen::Vector3d::Zero();  // unit, model coordinates
  int candidates = 0;                                 // near-vertical segments over all images
  int inliers = 0;                                    // segments whose plane contains upModel
  int imagesWithLines = 0;                            // images holding at least one inlier
  double rmsResidualDeg = 0;                          // inliers' planes from containing upModel
  std::string message;                                // why not found
};

// Reads the model's registered images from `imageFolder` (by name; missing or unreadable images
// are skipped) and finds the vertical. `found` is false, with a message, when too few lines
// agree (a landscape, a forest, footage without buildings).
VerticalLineGravity verticalFromLines(const ColmapModel& model,
                                      const std::filesystem::path& imageFolder,
                                      const VerticalLineOptions& options = {});

}  // namespace pluvia::sfm
