#include "rain/drop_volume.h"

#include <algorithm>
#include <cmath>

#include "rain/drop_physics.h"
#include "util/hash.h"

namespace pluvia::rain {

DropVolume::DropVolume(const Camera& camera, const DropVolumeParams& params) {
  // World-axis bounding box of the frustum between near and far.
  boxMin_ = Eigen::Vector3d::Constant(1e30);
  Eigen::Vector3d boxMax = Eigen::Vector3d::Constant(-1e30);
  for (double distance : {params.nearMeters, params.farMeters}) {
    for (double px : {0.0, double(camera.width)}) {
      for (double py : {0.0, double(camera.height)}) {
        Eigen::Vector3d corner = camera.positionMeters + camera.worldFromCamera * (camera.rayCamera(px, py) * distance);
        boxMin_ = boxMin_.cwiseMin(corner);
        boxMax = boxMax.cwiseMax(corner);
      }
    }
  }
  boxSize_ = boxMax - boxMin_;
  const double volumeCubicMeters = boxSize_.prod();
  physicalCount_ = dropsPerCubicMeter(params.rainRateMmPerHour, params.minDiameterMm, params.maxDiameterMm) *
                   params.densityScale * volumeCubicMeters;
  const auto count = static_cast<size_t>(std::min<double>(std::llround(physicalCount_), params.maxDrops));
  drops_.resize(count);
  for (size_t i = 0; i < count; ++i) {
    CounterRng rng(params.seed, i);
    Drop& drop = drops_[i];
    Eigen::Vector3d u(rng.uniform(), rng.uniform(), rng.uniform());
    drop.startMeters = (boxMin_ + u.cwiseProduct(boxSize_)).cast<float>();
    double diameterMm =
        sampleDiameterMm(rng.uniform(), params.rainRateMmPerHour, params.minDiameterMm, params.maxDiameterMm);
    drop.diameterMm = static_cast<float>(diameterMm * params.sizeScale);
    Eigen::Vector3d velocity = params.windMetersPerSecond;
    velocity.y() = -terminalVelocityMetersPerSecond(diameterMm);
    drop.velocityMetersPerSecond = velocity.cast<float>();
  }
}

Eigen::Vector3d DropVolume::positionAt(size_t i, double timeSeconds) const {
  const Drop& drop = drops_[i];
  Eigen::Vector3d p = drop.startMeters.cast<double>() + drop.velocityMetersPerSecond.cast<double>() * timeSeconds;
  for (int axis = 0; axis < 3; ++axis) {
    double offset = std::fmod(p[axis] - boxMin_[axis], boxSize_[axis]);
    if (offset < 0) offset += boxSize_[axis];
    p[axis] = boxMin_[axis] + offset;
  }
  return p;
}

std::vector<gpu::StreakInstance> buildStreaks(const DropVolume& volume, const Camera& camera, double timeSeconds,
                                              const StreakParams& params) {
  std::vector<gpu::StreakInstance> streaks;
  streaks.reserve(volume.drops().size());
  const double marginPx = 8.0;
  for (size_t i = 0; i < volume.drops().size(); ++i) {
    const Drop& drop = volume.drops()[i];
    Eigen::Vector3d start = volume.positionAt(i, timeSeconds);
    Eigen::Vector3d end = start + drop.velocityMetersPerSecond.cast<double>() * params.exposureSeconds;
    double hx, hy, hz, tx, ty, tz;
    const double minDepth = 0.05;
    if (!camera.project(start, hx, hy, hz, minDepth) || !camera.project(end, tx, ty, tz, minDepth)) continue;
    if (std::max(hx, tx) < -marginPx || std::min(hx, tx) > camera.width + marginPx) continue;
    if (std::max(hy, ty) < -marginPx || std::min(hy, ty) > camera.height + marginPx) continue;
    const double depthMeters = 0.5 * (hz + tz);
    const double widthPx = camera.focalPx * drop.diameterMm * 1e-3 / depthMeters;
    const double lengthPx = std::hypot(tx - hx, ty - hy);
    const double drawnWidthPx = std::max(widthPx, params.minWidthPx);
    const double timeFraction = widthPx / std::max(lengthPx, widthPx);
    const double coverage = widthPx / drawnWidthPx;
    const double fog = std::exp(-params.fogDensityPerMeter * depthMeters);
    const double alpha = std::min(1.0, params.opacity * timeFraction * coverage * fog / params.meanMatte);
    if (alpha < 1.0 / 1024.0) continue;  // invisible in any 10-bit output
    Eigen::Vector3d view = (start - camera.positionMeters).normalized();
    CounterRng rng(params.seed ^ 0x5712u, i);
    gpu::StreakInstance s{};
    s.headX = float(hx);
    s.headY = float(hy);
    s.tailX = float(tx);
    s.tailY = float(ty);
    s.widthPx = float(drawnWidthPx);
    s.alpha = float(alpha);
    s.depthMeters = float(depthMeters);
    s.strokeIndex = float(std::min<uint64_t>(params.strokeCount - 1, rng.nextU64() % std::max(1, params.strokeCount)));
    s.viewX = float(view.x());
    s.viewY = float(view.y());
    s.viewZ = float(view.z());
    streaks.push_back(s);
  }
  return streaks;
}

}  // namespace pluvia::rain
