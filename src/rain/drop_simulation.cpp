#include "rain/drop_simulation.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "rain/drop_glint.h"
#include "rain/thin_lens.h"
#include "util/hash.h"
#include "util/parallel.h"

namespace pluvia::rain {
namespace {

constexpr double kGravity = 9.81;            // m/s^2
constexpr int64_t kMaxScannedFrames = 4096;  // frames sampled to size the pool and the box

// The camera's heading frame: a rotation about +Y taking the frame's -Z to the camera's
// forward direction projected on the ground (the box follows the heading, not pitch or roll,
// so that drops keep falling along the box's -Y).
Eigen::Matrix3d headingOf(const Camera& camera) {
  const Eigen::Vector3d forward = camera.worldFromCamera * Eigen::Vector3d(0, 0, -1);
  const double yaw = std::atan2(forward.x(), -forward.z());  // 0 when looking along -Z
  return Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
}

// Frames first..last, every one when few, else evenly spread (both ends included).
std::vector<double> scannedFrames(int64_t first, int64_t last) {
  std::vector<double> frames;
  const int64_t count = std::max<int64_t>(1, last - first + 1);
  const int64_t samples = std::min(count, kMaxScannedFrames);
  for (int64_t k = 0; k < samples; ++k)
    frames.push_back(samples == 1
                         ? double(first)
                         : double(first) + double(count - 1) * double(k) / double(samples - 1));
  return frames;
}

double physicalDensity(const DropSimulationSettings& s, const RainAtFrame& rain) {
  return dropsPerCubicMeter(s.distribution, rain.rateMmPerHour, s.minDiameterMm, s.maxDiameterMm) *
         rain.densityScale;
}

}  // namespace

DropSimulation::DropSimulation(const DropSimulationSettings& settings, CameraAtFrame cameraAt,
                               RainAt rainAt)
    : settings_(settings), cameraAt_(std::move(cameraAt)), rainAt_(std::move(rainAt)) {
  settings_.lastFrame = std::max(settings_.lastFrame, settings_.firstFrame);
  // The box: the union over the shot of the frustum between near and far, each in its camera's
  // heading frame, grown by the margin.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e30), hi = Eigen::Vector3d::Constant(-1e30);
  double densest = 0.0;
  for (double f : scannedFrames(settings_.firstFrame, settings_.lastFrame)) {
    const Camera camera = cameraAt_(f);
    const Eigen::Matrix3d toHeading = headingOf(camera).transpose();
    for (double distance : {settings_.nearMeters, settings_.farMeters})
      for (double px : {0.0, double(camera.width)})
        for (double py : {0.0, double(camera.height)}) {
          const Eigen::Vector3d corner =
              toHeading * (camera.worldFromCamera * (camera.rayCamera(px, py) * distance));
          lo = lo.cwiseMin(corner);
          hi = hi.cwiseMax(corner);
        }
    densest = std::max(densest, physicalDensity(settings_, rainAt_(f)));
  }
  const Eigen::Vector3d margin = (hi - lo) * std::max(0.0, settings_.boxMarginFraction);
  boxLo_ = lo - margin;
  boxSize_ = (hi - lo + 2.0 * margin).cwiseMax(Eigen::Vector3d::Constant(1e-3));
  cells_ = std::make_unique<RainCells>(settings_.cells, Eigen::Vector2d::Zero());
  densest *= cells_->maxDensityFactor();
  wantedPoolSize_ = std::ceil(densest * boxVolumeCubicMeters());
  const double pool = std::min(wantedPoolSize_, double(std::max<int64_t>(0, settings_.maxDrops)));
  positions_.resize(size_t(pool));
  horizontalSpeed_.resize(positions_.size());
  sizeUniform_.resize(positions_.size());
  activeUniform_.resize(positions_.size());
  ownGaussian_.resize(positions_.size());
  poolDensity_ = double(positions_.size()) / boxVolumeCubicMeters();
  restartAt(settings_.firstFrame);
}

DropSimulation::~DropSimulation() = default;

double DropSimulation::boxVolumeCubicMeters() const {
  return boxSize_.prod();
}

void DropSimulation::restartAt(int64_t segmentStart) {
  const int64_t first = settings_.firstFrame;
  const double dt = settings_.stepSeconds;
  segmentStart_ = segmentStart;
  frame_ = segmentStart;
  // The wind: its clock (t = 0 at the first frame) set to the warm-up's start, its fluid warmed
  // up from rest to the segment's start as the steps would have driven it.
  const int64_t warmStart = segmentStart - std::max<int64_t>(0, settings_.windWarmupFrames);
  const RainAtFrame atWarmStart = rainAt_(double(warmStart));
  WindSettings wind = settings_.wind;
  wind.speedMetersPerSecond = atWarmStart.windSpeedMetersPerSecond;
  wind.directionDeg = atWarmStart.windDirectionDeg;
  wind_ = std::make_unique<WindField>(wind);
  constexpr uint64_t kStepOrigin = uint64_t(1) << 40;  // keeps the forcing's step index >= 0
  wind_->startAt(double(warmStart - first) * dt, kStepOrigin + uint64_t(warmStart - first));
  // The rain cells: laid out around the first frame's camera, carried to the warm-up's start by
  // the base wind's closed-form drift, then by the warming wind.
  const Camera firstCamera = cameraAt_(double(first));
  cells_ = std::make_unique<RainCells>(
      settings_.cells,
      Eigen::Vector2d(firstCamera.positionMeters.x(), firstCamera.positionMeters.z()));
  if (!cells_->centersXZ().empty()) {
    Eigen::Vector2d drift = Eigen::Vector2d::Zero();
    const int64_t from = std::min(first, warmStart), to = std::max(first, warmStart);
    for (int64_t f = from; f < to; ++f) {
      const RainAtFrame r = rainAt_(double(f));
      const double d = r.windDirectionDeg * M_PI / 180.0;
      const double t = double(f - first) * dt;
      drift += r.windSpeedMetersPerSecond * Eigen::Vector2d(std::cos(d), -std::sin(d)) *
               (wind_->gustIntegral(t + dt) - wind_->gustIntegral(t));
    }
    cells_->translate(warmStart >= first ? drift : Eigen::Vector2d(-drift));
  }
  for (int64_t f = warmStart; f < segmentStart; ++f) {
    const RainAtFrame r = rainAt_(double(f));
    wind_->setBase(r.windSpeedMetersPerSecond, r.windDirectionDeg);
    wind_->advance(dt);
    cells_->advance(dt, *wind_);
    ++windSteps_;
  }
  // The drops: a fresh layout per segment (the first segment's from the seed itself).
  const uint64_t segment =
      uint64_t((segmentStart - first) / std::max<int64_t>(1, settings_.segmentFrames));
  const uint64_t seed = settings_.seed ^ (0x9E3779B97F4A7C15ull * segment);
  const Camera camera = cameraAt_(double(frame_));
  const Eigen::Matrix3d heading = headingOf(camera);
  forEachIndex(positions_.size(), [&](size_t i) {
    CounterRng rng(seed, i);
    const Eigen::Vector3d u(rng.uniform(), rng.uniform(), rng.uniform());
    const Eigen::Vector3d p = camera.positionMeters + heading * (boxLo_ + u.cwiseProduct(boxSize_));
    positions_[i] = p.cast<float>();
    sizeUniform_[i] = float(rng.uniform());
    activeUniform_[i] = float(rng.uniform());
    // A Gaussian horizontal speed of its own (Box-Muller), on top of the wind.
    const double radius = std::sqrt(-2.0 * std::log(1.0 - rng.uniform()));
    const double angle = 2.0 * M_PI * rng.uniform();
    ownGaussian_[i] =
        Eigen::Vector2f(float(radius * std::cos(angle)), float(radius * std::sin(angle)));
  });
  baseDiameterMm_.clear();  // the sizes follow from the uniforms just drawn
  setRain(rainAt_(double(frame_)));
  forEachIndex(positions_.size(), [&](size_t i) {
    const Eigen::Vector3d w = wind_->velocityAt(positions_[i].x(), positions_[i].z());
    horizontalSpeed_[i] = (Eigen::Vector2d(w.x(), w.z()) + ownSpeed(i)).cast<float>();
  });
}

int64_t DropSimulation::segmentStartOf(int64_t frame) const {
  const int64_t first = settings_.firstFrame;
  if (frame <= first) return first;
  const int64_t length = std::max<int64_t>(1, settings_.segmentFrames);
  return first + (frame - first) / length * length;
}

Eigen::Vector2d DropSimulation::ownSpeed(size_t i) const {
  const double sigma =
      settings_.spreadMetersPerSecond + settings_.eddyIntensity * rain_.windSpeedMetersPerSecond;
  return sigma * ownGaussian_[i].cast<double>();
}

void DropSimulation::advanceTo(int64_t frame) {
  const int64_t start = segmentStartOf(frame);
  if (start != segmentStart_ || frame < frame_) restartAt(start);
  while (frame_ < frame) step();
}

// A drop's diameter and fall speed: cached per drop for the current rate; a rain cell scales
// the diameter where it passes, and the speed is then recomputed.
std::pair<double, double> DropSimulation::sizeAndFall(size_t i, double x, double z) const {
  const double cellSizeFactor = cells_->sizeFactor(x, z);
  if (cellSizeFactor == 1.0) return {double(baseDiameterMm_[i]), double(baseFall_[i])};
  const double d = double(baseDiameterMm_[i]) * cellSizeFactor;
  return {d, terminalVelocity(settings_.velocityModel, d)};
}

void DropSimulation::step() {
  const double dt = settings_.stepSeconds;
  // The parameters at the start of the step hold over it.
  wind_->setBase(rain_.windSpeedMetersPerSecond, rain_.windDirectionDeg);
  wind_->advance(dt);
  cells_->advance(dt, *wind_);
  const Camera camera = cameraAt_(double(frame_ + 1));
  const Eigen::Matrix3d heading = headingOf(camera);
  const Eigen::Matrix3d toHeading = heading.transpose();
  forEachBlock(positions_.size(), 4096, [&](size_t begin, size_t end) {
    for (size_t i = begin; i != end; ++i) {
      Eigen::Vector3d p = positions_[i].cast<double>();
      const double fall = sizeAndFall(i, p.x(), p.z()).second;
      // Horizontal speed relaxes toward the wind with tau = v_t / g; exact for a
      // wind held over the step, so any step is stable.
      const double tau = std::max(fall / kGravity, 1e-3);
      const double a = -std::expm1(-dt / tau);
      const Eigen::Vector3d w = wind_->velocityAt(p.x(), p.z());
      Eigen::Vector2d v = horizontalSpeed_[i].cast<double>();
      const Eigen::Vector2d wh = Eigen::Vector2d(w.x(), w.z()) + ownSpeed(i);
      const Eigen::Vector2d travelled = wh * dt + (v - wh) * tau * a;
      v = wh + (v - wh) * (1.0 - a);
      p += Eigen::Vector3d(travelled.x(), -fall * dt, travelled.y());
      // 3-D wrap-around in the box that follows the camera.
      Eigen::Vector3d local = toHeading * (p - camera.positionMeters) - boxLo_;
      for (int axis = 0; axis < 3; ++axis) {
        local[axis] -= boxSize_[axis] * std::floor(local[axis] / boxSize_[axis]);
      }
      p = camera.positionMeters + heading * (local + boxLo_);
      positions_[i] = p.cast<float>();
      horizontalSpeed_[i] = v.cast<float>();
    }
  });
  ++frame_;
  ++dropSteps_;
  ++windSteps_;
  setRain(rainAt_(double(frame_)));
}

void DropSimulation::setRain(const RainAtFrame& rain) {
  const bool sizesChange = rain.rateMmPerHour != rain_.rateMmPerHour || baseDiameterMm_.empty();
  rain_ = rain;
  if (sizesChange) {
    baseDiameterMm_.resize(positions_.size());
    baseFall_.resize(positions_.size());
    forEachIndex(positions_.size(), [&](size_t i) {
      const double d =
          sampleDiameterMm(settings_.distribution, double(sizeUniform_[i]), rain_.rateMmPerHour,
                           settings_.minDiameterMm, settings_.maxDiameterMm);
      baseDiameterMm_[i] = float(d);
      baseFall_[i] = float(terminalVelocity(settings_.velocityModel, d));
    });
  }
  drawnFraction_ = poolDensity_ > 0.0 ? physicalDensityPerCubicMeter() / poolDensity_ : 0.0;
}

double DropSimulation::physicalDensityPerCubicMeter() const {
  return physicalDensity(settings_, rain_);
}

// Drop i is drawn while its threshold lies below the local density over the pool's.
bool DropSimulation::isActive(size_t i) const {
  return double(activeUniform_[i]) <
         drawnFraction_ * cells_->densityFactor(positions_[i].x(), positions_[i].z());
}

size_t DropSimulation::activeCount() const {
  size_t count = 0;
  for (size_t i = 0; i < positions_.size(); ++i) count += isActive(i);
  return count;
}

bool DropSimulation::insideBox(const Eigen::Vector3d& worldMeters) const {
  const Camera camera = cameraAt_(double(frame_));
  const Eigen::Vector3d local =
      headingOf(camera).transpose() * (worldMeters - camera.positionMeters) - boxLo_;
  for (int axis = 0; axis < 3; ++axis)
    if (local[axis] < -1e-4 || local[axis] > boxSize_[axis] + 1e-4) return false;
  return true;
}

namespace {

struct StreakQuadFit {
  double headX, headY, tailX, tailY, widthPx;
  double alphaScale;  // the old quad's area over the new one's: the streak's energy is kept
};

// The quad that makes a stroke's own size the streak's: its equivalent width that of a disc
// swept along the path (pi/4 of the drawn diameter), its half-maximum length the path and the
// drop together (hypot: the path for a long streak, the disc for a still drop). The rectangle
// around it is `scale` = {across, along} times larger (strokeQuadScales()).
StreakQuadFit fitStrokeToStreak(double hx, double hy, double tx, double ty, double widthPx,
                                std::array<float, 2> scale) {
  if (scale[0] == 1.0f && scale[1] == 1.0f) return {hx, hy, tx, ty, widthPx, 1.0};
  const double lengthPx = std::hypot(tx - hx, ty - hy);
  const double quadWidthPx = scale[0] * 0.25 * M_PI * widthPx;
  const double quadAlongPx = std::max(scale[1] * std::hypot(lengthPx, widthPx), quadWidthPx);
  const double pathPx = quadAlongPx - quadWidthPx;
  // A still drop keeps the vertical axis the quad takes for it (gpu/streak_quad.h).
  const bool moving = lengthPx > 1e-4;
  const double axisX = moving ? (tx - hx) / lengthPx : 0.0;
  const double axisY = moving ? (ty - hy) / lengthPx : 1.0;
  const double cx = 0.5 * (hx + tx), cy = 0.5 * (hy + ty);
  return {cx - 0.5 * pathPx * axisX,
          cy - 0.5 * pathPx * axisY,
          cx + 0.5 * pathPx * axisX,
          cy + 0.5 * pathPx * axisY,
          quadWidthPx,
          (lengthPx + widthPx) * widthPx / (quadAlongPx * quadWidthPx)};
}

}  // namespace

std::vector<StreakInstance> DropSimulation::buildStreaks(
    const StreakSettings& s, std::vector<StreakInstance>* farStreaks) const {
  const Camera start = cameraAt_(double(frame_));
  const Camera end = cameraAt_(double(frame_) + s.exposureSeconds / settings_.stepSeconds);
  const ThinLens lens =
      ThinLens::of(start.focalPx, start.width, s.sensorWidthMm, s.focusMeters, s.fNumber);
  constexpr double kMarginPx = 8.0, kMinDepthMeters = 0.05;

  std::vector<StreakInstance> streaks;
  streaks.reserve(positions_.size() / 2);
  if (farStreaks) farStreaks->clear();
  for (size_t i = 0; i < positions_.size(); ++i) {
    const Eigen::Vector3d p = positions_[i].cast<double>();
    if (!isActive(i)) continue;
    const auto [d, fall] = sizeAndFall(i, p.x(), p.z());
    const Eigen::Vector3d v(horizontalSpeed_[i].x(), -fall, horizontalSpeed_[i].y());
    const Eigen::Vector3d q = p + v * s.exposureSeconds;
    double hx, hy, hz, tx, ty, tz;
    if (!start.project(p, hx, hy, hz, kMinDepthMeters) ||
        !end.project(q, tx, ty, tz, kMinDepthMeters))
      continue;
    if (std::max(hx, tx) < -kMarginPx || std::min(hx, tx) > start.width + kMarginPx) continue;
    if (std::max(hy, ty) < -kMarginPx || std::min(hy, ty) > start.height + kMarginPx) continue;
    const double depthMeters = 0.5 * (hz + tz);
    // The box's margins (for wrapping while the camera turns) reach past near and far: drops
    // there are not drawn.
    if (depthMeters < settings_.nearMeters || depthMeters > settings_.farMeters) continue;
    const double widthPx = start.focalPx * d * rain_.sizeScale * 1e-3 / depthMeters;
    const double blurPx = lens.blurPx(depthMeters);
    const double lengthPx = std::hypot(tx - hx, ty - hy);
    const double drawnWidthPx = std::max(widthPx + blurPx, s.minWidthPx);
    // The drop covers a point of its path for widthPx of the streak's lengthPx; the quad is
    // drawnWidthPx longer than the path (half at each end), so the fraction over its length
    // keeps the streak's alpha x area at the drop's projected area, widthPx^2.
    const double timeFraction = widthPx / (lengthPx + drawnWidthPx);
    const double coverage = widthPx / drawnWidthPx;
    const double fog = std::exp(-s.fogDensityPerMeter * depthMeters);
    CounterRng rng(settings_.seed ^ 0x5712u, i);
    const int strokeIndex =
        int(std::min<uint64_t>(uint64_t(std::max(1, s.strokeCount)) - 1,
                               rng.nextU64() % uint64_t(std::max(1, s.strokeCount))));
    const StreakQuadFit fit = fitStrokeToStreak(hx, hy, tx, ty, drawnWidthPx,
                                                size_t(strokeIndex) < s.strokeQuadScale.size()
                                                    ? s.strokeQuadScale[size_t(strokeIndex)]
                                                    : std::array<float, 2>{1.0f, 1.0f});
    // The drop's alpha over its own path and width; a drop under 1/1024 there is invisible in
    // any 10-bit output (and never NaN). The stroke's soft margins then spread it thinner.
    const double pathAlpha = s.opacity * timeFraction * coverage * fog / s.meanMatte;
    if (!(pathAlpha >= 1.0 / 1024.0)) continue;
    const double alpha = std::min(1.0, pathAlpha * fit.alphaScale);
    const Eigen::Vector3d view = (p - start.positionMeters).normalized();
    StreakInstance streak{};
    streak.headX = float(fit.headX);
    streak.headY = float(fit.headY);
    streak.tailX = float(fit.tailX);
    streak.tailY = float(fit.tailY);
    streak.widthPx = float(fit.widthPx);
    streak.alpha = float(alpha);
    streak.depthMeters = float(depthMeters);
    streak.strokeIndex = float(strokeIndex);
    streak.viewX = float(view.x());
    streak.viewY = float(view.y());
    streak.viewZ = float(view.z());
    // The drop oscillates (Garg and Nayar): periods of mode (2, 0) over the exposure, from a
    // random instant, one of their two shape sets and a random orientation phi_rot about the
    // vertical (rain/drop_glint.h). Bounded so that the phase stays exact in float (a still
    // frame of a tiny drop).
    const double diameterMm = d * rain_.sizeScale;
    streak.beadCycles =
        float(std::min(1e3, oscillationFrequencyHz(diameterMm) * s.exposureSeconds));
    streak.beadPhase = float(rng.uniform());
    streak.glintMode20 = kOscillationAmplitude20[rng.uniform() < 0.5 ? 0 : 1];
    streak.glintMode31 = kOscillationAmplitude31 * float(std::cos(2.0 * M_PI * rng.uniform()));
    if (farStreaks && widthPx < s.lodPx) {
      farStreaks->push_back(streak);
    } else {
      streaks.push_back(streak);
    }
  }
  return streaks;
}

}  // namespace pluvia::rain
