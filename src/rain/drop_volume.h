#pragma once
// The drops: a box in world space around the camera's view frustum (between near and far),
// filled uniformly (Wang et al.: position is a uniform random variable) and wrapped in all three
// axes, so that every frame's drops follow in closed form from (seed, drop index, time). Frame N
// is therefore the same whether it is rendered alone, in a chunk or in a full run.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "gpu/rain_renderer.h"

namespace pluvia::rain {

struct DropVolumeParams {
  double rainRateMmPerHour = 15.0;
  double minDiameterMm = 0.8;   // smaller drops read as haze, not streaks; left to fog
  double maxDiameterMm = 6.0;   // larger drops break up
  double densityScale = 1.0;    // artist override on the physical count
  double sizeScale = 1.0;       // artist override on the drawn diameter
  double nearMeters = 0.5;
  double farMeters = 15.0;
  int64_t maxDrops = 100000;
  uint64_t seed = 1;
  Eigen::Vector3d windMetersPerSecond = Eigen::Vector3d::Zero();  // horizontal, world
};

struct Drop {
  Eigen::Vector3f startMeters;           // position at time 0, inside the box
  Eigen::Vector3f velocityMetersPerSecond;
  float diameterMm;
};

class DropVolume {
 public:
  DropVolume(const Camera& camera, const DropVolumeParams& params);

  const std::vector<Drop>& drops() const { return drops_; }
  // The physical count before the max_drops cap (for `pluvia plan` and warnings).
  double physicalCount() const { return physicalCount_; }
  Eigen::Vector3d boxMin() const { return boxMin_; }
  Eigen::Vector3d boxSize() const { return boxSize_; }
  // Position of drop i at the time, wrapped into the box.
  Eigen::Vector3d positionAt(size_t i, double timeSeconds) const;

 private:
  std::vector<Drop> drops_;
  Eigen::Vector3d boxMin_;
  Eigen::Vector3d boxSize_;
  double physicalCount_ = 0.0;
};

struct StreakParams {
  double exposureSeconds = 0.02;
  double opacity = 1.0;               // artist scale on the physical alpha
  double fogDensityPerMeter = 0.0;    // drops fade into the fog with exp(-density * depth)
  double minWidthPx = 1.5;            // thinner streaks are drawn this wide with less alpha
  int strokeCount = 1;                // strokes in the atlas; drop i uses one chosen by its seed
  // Mean matte value over a stroke's rectangle: alpha is divided by it so that the drawn
  // matte, integrated over the quad, carries the drop's physical coverage.
  double meanMatte = 1.0;
  uint64_t seed = 1;
};

// Projects every drop's motion during the exposure [t, t + exposure] into a screen streak.
// Alpha follows Garg and Nayar: the fraction of the exposure a drop covers a pixel on its
// streak, widthPx / lengthPx (= 2r / (v T) for motion across the view), times the fraction
// of a drawn pixel the drop covers when it is thinner than minWidthPx, divided by the matte's
// mean so that the shaped stroke carries the same total coverage as a flat one.
std::vector<gpu::StreakInstance> buildStreaks(const DropVolume& volume, const Camera& camera, double timeSeconds,
                                              const StreakParams& params);

}  // namespace pluvia::rain
