#pragma once
// The camera that films the rain over the clip: static (one Camera), a keyframed path from the
// preset (camera.path), or per-frame poses (tracked footage, e.g. COLMAP). Frames are clip frame
// numbers (the numbers the renderer calls `frame`) and may be fractional: the rain renderer asks
// for frame + exposure fraction to get the camera at the end of the exposure.
//
// Pose convention (pluvia's world frame, camera.h): +Y up, metres; with yaw = pitch = roll = 0 the
// camera looks along world -Z with +Y up and +X to the right.
//   yawDeg:   positive turns right, from -Z toward +X (a rotation of -yaw about world +Y).
//   pitchDeg: positive looks up (a rotation of +pitch about the camera's +X).
//   Camera::fromFieldOfView's
//             tilt_deg is positive looking DOWN: pitchDeg = -tilt_deg.
//   rollDeg:  positive rolls clockwise as the camera sees it: its right side goes down (a
//             right-handed rotation of +roll about the viewing direction -Z).
// worldFromCamera = Ry(-yaw) * Rx(pitch) * Rz(-roll).
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/camera.h"

namespace pluvia {

struct CameraPose {
  Eigen::Vector3d positionMeters = Eigen::Vector3d::Zero();
  double yawDeg = 0.0;
  double pitchDeg = 0.0;
  double rollDeg = 0.0;
};

// The camera-to-world rotation of a pose (the convention above).
Eigen::Matrix3d worldFromCameraRotation(const CameraPose& pose);

// One key of a path given as a rotation (what a tracker hands over).
struct CameraPathKey {
  double frame = 0.0;
  Eigen::Vector3d positionMeters = Eigen::Vector3d::Zero();
  Eigen::Quaterniond worldFromCamera = Eigen::Quaterniond::Identity();
};

class CameraPath {
 public:
  CameraPath() = default;  // a fixed default Camera
  // Keys as poses, in strictly increasing frame order (per-frame poses are keys at every frame).
  // Intrinsics (size, focal length, principal point) come from `intrinsics`; its pose is
  // replaced by the keys'. No keys gives the fixed `intrinsics` camera. Throws pluvia::Error for
  // unsorted or duplicate frames or non-finite values.
  CameraPath(const Camera& intrinsics, const std::vector<std::pair<double, CameraPose>>& keys);

  // The same camera at every frame.
  static CameraPath fixed(const Camera& camera);
  // Same as the constructor.
  static CameraPath fromKeys(const Camera& intrinsicsAndBase,
                             std::vector<std::pair<double, CameraPose>> keys);
  // Keys given as rotations (same rules as the constructor).
  static CameraPath fromRotations(const Camera& intrinsics, std::vector<CameraPathKey> keys);

  // The camera at a (fractional) clip frame: positions interpolate linearly, orientations by
  // quaternion slerp (the shorter way round: yaw 350 -> 10 passes through 0). Before the first key
  // the first pose holds, after the last the last.
  Camera cameraAt(double frame) const;
  // True when the pose changes over frames.
  bool moving() const;
  // The keys (empty for a fixed path).
  const std::vector<CameraPathKey>& keys() const { return keys_; }

 private:
  Camera base_;
  std::vector<CameraPathKey> keys_;
};

}  // namespace pluvia
