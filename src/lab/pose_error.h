#pragma once
// How far an estimated camera path (structure from motion) is from the true one, and an
// estimated depth map from the true depth: what `pluvia report depth` measures.
//
// The SfM world (sfm_poses.h) is levelled and metric, its ground at y = 0, but its heading and
// horizontal origin are arbitrary, so the estimate is aligned to the truth before comparing:
//  - rotation: the chordal L2 mean of R_true_i * R_est_i^T over the frames (R = worldFromCamera),
//    projected onto SO(3) (SVD). It needs no spread of camera centres, unlike Umeyama on the
//    centres, which is ill-conditioned when the camera walks a nearly straight line.
//  - translation: the one that maps the estimate's mean centre onto the truth's, with the
//    rotation above and WITHOUT re-fitting scale: the metric scale hint is part of what is
//    measured, so a wrong scale shows as position error. The least-squares scale of the rotated,
//    centred estimate against the centred truth is reported on its own (estimate / truth).
// Per frame: rotation error = angle of R_true^T * R_align * R_est; position error = distance of
// R_align * c_est + t from c_true.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"

namespace pluvia::lab {

struct PoseAlignment {
  // truthWorld = rotation * estimateWorld + translationMeters
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translationMeters = Eigen::Vector3d::Zero();
};

struct PoseErrors {
  PoseAlignment alignment;
  std::vector<double> rotationErrorDeg;     // per frame, in the order given
  std::vector<double> positionErrorMeters;  // per frame, after alignment (scale not re-fitted)
  double meanRotationErrorDeg = 0.0;
  double maxRotationErrorDeg = 0.0;
  double meanPositionErrorMeters = 0.0;
  double maxPositionErrorMeters = 0.0;
  // Least-squares scale of the estimate's centred path against the truth's (1: metric scale
  // right; 1.1: the estimate is 10 % too large). NaN when the true centres do not spread.
  double scaleRatio = 0.0;
  // Tilt of the alignment rotation: the angle between its up axis and +Y. The estimate's world
  // is meant to be levelled already, so this is its levelling error, in degrees.
  double levelErrorDeg = 0.0;
  // Mean camera height (y) of the estimate minus the truth's, before alignment: both worlds put
  // the ground at y = 0.
  double heightOffsetMeters = 0.0;
};

// Aligns `estimate` to `truth` (same length, at least one frame, matching frames at matching
// indices) and measures the errors. Throws pluvia::Error when the lengths differ or are zero.
PoseErrors comparePoses(const std::vector<Camera>& truth, const std::vector<Camera>& estimate);

// Angle of a rotation matrix, degrees (0 to 180), robust near 0 and 180.
double rotationAngleDeg(const Eigen::Matrix3d& rotation);

// Depth maps compared pixel by pixel (z-depth in metres, +inf for sky). Several frames may be
// pooled into one accumulator: the median is over all their pixels.
struct DepthErrors {
  // Median and 90th percentile of |d_est - d_true| / d_true over pixels where both are finite
  // and positive (NaN when there are none).
  double medianRelativeError = 0.0;
  double p90RelativeError = 0.0;
  size_t comparedPixels = 0;
  size_t skyPixels = 0;     // truth +inf
  size_t nonSkyPixels = 0;  // truth finite
  // Of the true sky, the fraction estimated +inf (1 is right); of the rest, the fraction
  // estimated +inf (0 is right). NaN when the truth has no such pixel.
  double skyAsInfinityFraction = 0.0;
  double nonSkyAsInfinityFraction = 0.0;
};

class DepthErrorAccumulator {
 public:
  // `truth` and `estimate` have the same length; `include` (same length, nonzero = counted)
  // limits the comparison to some pixels. Throws pluvia::Error when the lengths differ.
  void add(const std::vector<float>& truth, const std::vector<float>& estimate,
           const std::vector<uint8_t>* include = nullptr);
  DepthErrors result() const;

 private:
  std::vector<float> relativeErrors_;
  size_t skyPixels_ = 0, skyAsInfinity_ = 0, nonSkyPixels_ = 0, nonSkyAsInfinity_ = 0;
};

// One pair of depth maps.
DepthErrors compareDepth(const std::vector<float>& truth, const std::vector<float>& estimate,
                         const std::vector<uint8_t>* include = nullptr);

}  // namespace pluvia::lab
