#pragma once
// Splash fields and impacts kept from one frame to the next. Both are pure functions of their
// inputs (the camera, the depth plane, the settings, the rate), so a frame gets the same result
// whether it was kept or made anew, and a chunk renders the frames a whole run does. A
// locked-off camera over a static depth (layers, the scene priors, a still depth file) makes
// its field once per chunk and each birth frame's impacts once; a moving camera or a changing
// depth makes the field every frame, and the impacts of every birth frame alive in it.
#include <cstdint>
#include <map>
#include <vector>

#include "geometry/camera.h"
#include "rain/splash_rate.h"
#include "rain/splashes.h"

namespace pluvia::rain {

struct SplashFieldInputs {
  double maxTiltDeg = 30.0;
  double maxDepthMeters = 0.0;  // the level of detail's limit (upFacingAreaPerPixel)
  double impactsPerSquareMeterSecond = 0.0;
  int tilePx = 32;
  bool operator==(const SplashFieldInputs&) const = default;
};

class SplashMemo {
 public:
  // Makes `camera`'s field of `depth` and its tiles, unless they are the last call's.
  void setField(const Camera& camera, const std::vector<float>& depth,
                const SplashFieldInputs& inputs);
  const SplashField& field() const { return field_; }
  const SplashTiles& tiles() const { return tiles_; }

  // The impacts born in birth frames first..last on the field (impactsBorn in splashes.h),
  // those not kept made in parallel; `rateMmPerHour` identifies `diameters`. Birth frames
  // before `first` are forgotten.
  std::vector<const std::vector<Impact>*> impacts(int64_t first, int64_t last, double fps,
                                                  uint64_t seed, const ImpactDiameters& diameters,
                                                  double rateMmPerHour, VelocityModel velocity);

 private:
  Camera camera_;
  SplashFieldInputs inputs_;
  bool haveField_ = false;
  SplashField field_;
  SplashTiles tiles_;
  // Kept impacts, valid for the field above and these:
  double fps_ = 0.0, rate_ = -1.0;
  uint64_t seed_ = 0;
  VelocityModel velocity_ = VelocityModel::Atlas;
  std::map<int64_t, std::vector<Impact>> born_;
};

}  // namespace pluvia::rain
