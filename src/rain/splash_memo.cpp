#include "rain/splash_memo.h"

#include "util/parallel.h"

namespace pluvia::rain {
namespace {

bool sameCamera(const Camera& a, const Camera& b) {
  return a.width == b.width && a.height == b.height && a.focalPx == b.focalPx && a.cx == b.cx &&
         a.cy == b.cy && a.worldFromCamera == b.worldFromCamera &&
         a.positionMeters == b.positionMeters;
}

}  // namespace

void SplashMemo::setField(const Camera& camera, const std::vector<float>& depth,
                          const SplashFieldInputs& inputs) {
  if (haveField_ && inputs == inputs_ && sameCamera(camera, camera_) && depth == field_.depth)
    return;
  camera_ = camera;
  inputs_ = inputs;
  field_.depth = depth;
  field_.areaPerPixel =
      upFacingAreaPerPixel(camera, depth, inputs.maxTiltDeg, inputs.maxDepthMeters);
  field_.impactsPerSquareMeterSecond = inputs.impactsPerSquareMeterSecond;
  field_.tilePx = inputs.tilePx;
  tiles_ = splashTiles(field_, camera.width, camera.height);
  haveField_ = true;
  born_.clear();
}

std::vector<const std::vector<Impact>*> SplashMemo::impacts(int64_t first, int64_t last, double fps,
                                                            uint64_t seed,
                                                            const ImpactDiameters& diameters,
                                                            double rateMmPerHour,
                                                            VelocityModel velocity) {
  if (fps != fps_ || seed != seed_ || rateMmPerHour != rate_ || velocity != velocity_) {
    born_.clear();
    fps_ = fps, seed_ = seed, rate_ = rateMmPerHour, velocity_ = velocity;
  }
  born_.erase(born_.begin(), born_.lower_bound(first));
  std::vector<int64_t> missing;
  for (int64_t b = first; b <= last; ++b)
    if (!born_.count(b)) missing.push_back(b);
  std::vector<std::vector<Impact>> made(missing.size());
  forEachIndex(missing.size(), [&](size_t k) {
    made[k] = impactsBorn(field_, tiles_, camera_, missing[k], fps, seed, diameters, velocity);
  });
  for (size_t k = 0; k < missing.size(); ++k) born_[missing[k]] = std::move(made[k]);
  std::vector<const std::vector<Impact>*> out;
  for (int64_t b = first; b <= last; ++b) out.push_back(&born_.at(b));
  return out;
}

}  // namespace pluvia::rain
