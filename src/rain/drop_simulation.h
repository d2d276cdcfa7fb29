#pragma once
// The drops as a simulation in world space (Mizukami et al. section 3): a box in front of the
// camera covering its view frustum, with 3-D wrap-around. A drop leaving a face re-enters from
// the opposite one, so the faces the drops leave by (their velocity relative to the camera
// picks them: the bottom for still air, the near face for a camera walking forward) are the
// vanishing faces and their opposites the generating ones, and the number of drops in the box
// never changes.
//
// Each step moves every drop by its fall speed (terminal velocity of its diameter) and its
// horizontal speed, which relaxes toward the local wind with the drop's drag time
// tau = v_t / g (exact exponential integrator: stable for any step). The box follows the
// camera's position and heading (yaw); its size is the union of the frusta over the whole
// camera path, so it never changes and wrapping stays a plain modulo.
//
// Rain rate, density, size and wind may change over the shot (ramps) and with position (rain
// cells): the pool holds the most drops the shot ever needs, and drop i is drawn only while its
// fixed random threshold lies below the local density over the pool's density.
//
// Determinism for farms: the state at frame N is reached by the same fixed steps (one per
// frame, from the clip's first frame) however the frames are split between processes, and
// every drop's randomness depends only on (seed, index); so frame N is byte-identical whether
// rendered alone, in a chunk or in a full run.
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera.h"
#include "rain/drop_physics.h"
#include "rain/rain_cells.h"
#include "rain/streak_types.h"
#include "rain/wind_field.h"

namespace pluvia::rain {

// The parameters that may be keyframed, at one frame.
struct RainAtFrame {
  double rateMmPerHour = 15.0;
  double densityScale = 1.0;
  double sizeScale = 1.0;  // artist scale on the drawn diameter (not the fall speed)
  double windSpeedMetersPerSecond = 0.0;
  double windDirectionDeg = 0.0;  // WindSettings convention
};

struct DropSimulationSettings {
  SizeDistribution distribution = SizeDistribution::MarshallPalmer;
  VelocityModel velocityModel = VelocityModel::Atlas;
  double minDiameterMm = 0.8;  // smaller drops read as haze, not streaks; left to fog
  double maxDiameterMm = 6.0;  // larger drops break up
  double nearMeters = 0.5;
  double farMeters = 15.0;
  double spreadMetersPerSecond = 0.0;  // per-drop random horizontal speed (std dev) on the wind
  // Small eddies, far smaller than the wind field's cells: each drop's own horizontal speed has a
  // further standard deviation of eddyIntensity times the wind speed (the turbulence intensity
  // near the ground is 0.1-0.3), so driven rain is not one parallel hatch.
  double eddyIntensity = 0.0;
  double boxMarginFraction = 0.1;  // of the box size on each side, so panning hides the wrap
  int64_t maxDrops = 100000;
  uint64_t seed = 1;
  double stepSeconds = 1.0 / 24.0;  // one frame
  int64_t firstFrame = 0;           // the clip's first frame: where the simulation starts
  // Any frame in constant time: the drops of frame N are simulated from the start of its
  // segment, firstFrame + a multiple of segmentFrames, where they are laid out afresh (a new
  // random layout per segment; rain is uncorrelated from frame to frame anyway, each drop
  // falling far more than the spacing of the drops in 1/24 s). The wind and the rain cells are
  // closed forms of the time (gusts, drift) plus a fluid warmed up over windWarmupFrames before
  // each segment, so they carry on across segments. A frame costs at most segmentFrames - 1
  // steps of the drops, whatever its number.
  int64_t segmentFrames = 24;
  int64_t windWarmupFrames = 240;
  int64_t lastFrame = 0;  // the clip's last frame (sizes the pool and the box)
  WindSettings wind;      // speed and direction are taken from RainAtFrame
  RainCellSettings cells;
};

using CameraAtFrame = std::function<Camera(double frame)>;
using RainAt = std::function<RainAtFrame(double frame)>;

struct StreakSettings {
  double exposureSeconds = 0.02;
  double opacity = 1.0;             // artist scale on the physical alpha
  double fogDensityPerMeter = 0.0;  // drops fade into the fog with exp(-density * depth)
  double minWidthPx = 1.5;          // thinner streaks are drawn this wide with less alpha
  int strokeCount = 1;              // strokes in the atlas; drop i uses one chosen by its seed
  // Mean matte value over a stroke's rectangle: alpha is divided by it so that the drawn
  // matte, integrated over the quad, carries the drop's physical coverage.
  double meanMatte = 1.0;
  // Per stroke, its rectangle over the matte's own equivalent width and half-maximum length
  // (strokeQuadScales() in rain/stroke_library.h): each quad grows by them so that the stroke
  // it carries, not its rectangle, has the streak's width and length. Empty: the rectangle is
  // the stroke (a synthetic atlas).
  std::vector<std::array<float, 2>> strokeQuadScale;
  // Defocus (thin lens): no blur when either is 0.
  double focusMeters = 0.0;
  double fNumber = 0.0;
  double sensorWidthMm = 36.0;
  // Level of detail (rain.lod_px): drops whose projected diameter (before defocus) is under
  // this many pixels are the far ones drawn as lines (gpu/far_drop_lines.h); 0: none.
  double lodPx = 0.0;
};

class DropSimulation {
 public:
  DropSimulation(const DropSimulationSettings& settings, CameraAtFrame cameraAt, RainAt rainAt);
  ~DropSimulation();

  // Steps forward to `frame`, from the start of its segment when it is not in the current one
  // or lies before the current frame (frames before firstFrame take firstFrame's drops).
  void advanceTo(int64_t frame);
  int64_t frame() const { return frame_; }
  // Steps of the drops and of the wind taken so far (the work a frame number costs).
  int64_t dropSteps() const { return dropSteps_; }
  int64_t windSteps() const { return windSteps_; }
  // The first frame of the segment `frame` is simulated in.
  int64_t segmentStartOf(int64_t frame) const;
  const DropSimulationSettings& settings() const { return settings_; }

  // Drops in the pool, and how many are drawn at the current frame (inside the density).
  size_t poolSize() const { return positions_.size(); }
  // The pool the densest frame of the shot (rain cells included) asks for, before maxDrops.
  double wantedPoolSize() const { return wantedPoolSize_; }
  size_t activeCount() const;
  bool isActive(size_t i) const;
  // Drops per cubic metre the physics asks for at the current frame, before the pool's cap.
  double physicalDensityPerCubicMeter() const;
  double boxVolumeCubicMeters() const;
  Eigen::Vector3d positionOf(size_t i) const { return positions_[i].cast<double>(); }
  // Whether the current camera's box (in its heading frame) holds the point.
  bool insideBox(const Eigen::Vector3d& worldMeters) const;

  // Every active drop's motion relative to the camera during the exposure that starts at the
  // current frame, projected into a screen streak. Alpha follows Garg and Nayar: the fraction
  // of the exposure a drop covers a pixel on its streak (widthPx / lengthPx = 2r / (v T) for
  // motion across the view; over the quad, which is drawnWidthPx longer than the path,
  // widthPx / (lengthPx + drawnWidthPx), so alpha x area is the drop's widthPx^2), times the
  // fraction of a drawn pixel the drop covers when thinner than minWidthPx, spread over the circle
  // of confusion when defocused, divided by the matte's mean.
  // farStreaks: when given, the streaks of drops under settings.lodPx go there instead (each
  // list in drop order); when null, every streak is returned.
  std::vector<StreakInstance> buildStreaks(const StreakSettings& settings,
                                           std::vector<StreakInstance>* farStreaks = nullptr) const;

 private:
  void restartAt(int64_t segmentStart);
  void step();
  void setRain(const RainAtFrame& rain);
  std::pair<double, double> sizeAndFall(size_t i, double xMeters, double zMeters) const;
  // The drop's own speed on the wind it follows at the current rain (spread and eddies).
  Eigen::Vector2d ownSpeed(size_t i) const;

  DropSimulationSettings settings_;
  CameraAtFrame cameraAt_;
  RainAt rainAt_;
  int64_t frame_ = 0;
  int64_t segmentStart_ = 0;
  int64_t dropSteps_ = 0, windSteps_ = 0;
  RainAtFrame rain_;
  Eigen::Vector3d boxLo_, boxSize_;  // in the camera's heading frame, relative to its position
  double poolDensity_ = 0.0;         // drops per cubic metre the pool holds
  double wantedPoolSize_ = 0.0;
  double drawnFraction_ = 0.0;  // physical density over the pool's, before the cells
  std::unique_ptr<WindField> wind_;
  std::unique_ptr<RainCells> cells_;
  std::vector<Eigen::Vector3f> positions_;        // world metres
  std::vector<Eigen::Vector2f> horizontalSpeed_;  // world x, z, m/s
  std::vector<Eigen::Vector2f> ownGaussian_;      // unit normal per drop: spread and eddies
  std::vector<float> sizeUniform_, activeUniform_;
  std::vector<float> baseDiameterMm_, baseFall_;  // at the current rate, outside rain cells
};

}  // namespace pluvia::rain
