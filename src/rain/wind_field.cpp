#include "rain/wind_field.h"

#include <algorithm>
#include <cmath>

#include "util/error.h"
#include "util/hash.h"

namespace pluvia::rain {

namespace {

constexpr int kDiffusionSweeps = 10;
constexpr int kPressureSweeps = 40;
constexpr int kSwirlsPerStep = 4;
constexpr double kClampOverRms = 4.0;
// Gust harmonics: weights sum to 1 (so the factor stays >= 0 for gustiness <= 1) and
// incommensurate frequency multipliers of 1 / gust period, so the pattern never repeats.
constexpr std::array<double, 3> kGustWeight = {0.5, 0.3, 0.2};
constexpr std::array<double, 3> kGustHarmonic = {1.0, 2.13, 4.37};
// Random streams of CounterRng(seed, stream): forcing step k uses stream k, gusts this one.
constexpr uint64_t kGustStream = 0xffffffff00000001ull;

// x - period * floor(x / period), kept in [0, period) against rounding.
double wrapInto(double x, double period) {
  double w = x - period * std::floor(x / period);
  return w >= period ? w - period : w;
}

// For d in (-period, period): the image of d nearest to 0.
double nearestImage(double d, double period) {
  if (d > 0.5 * period) return d - period;
  if (d < -0.5 * period) return d + period;
  return d;
}

}  // namespace

StableFluidGrid::StableFluidGrid(int size, double cellSizeMeters)
    : n_(std::clamp(size + size % 2, 8, 512)),
      h_(cellSizeMeters > 0.0 ? cellSizeMeters : 1.0),
      velocity_(size_t(n_) * n_, Eigen::Vector2d::Zero()),
      scratch_(velocity_.size()),
      pressure_(velocity_.size()),
      divergence_(velocity_.size()) {
  for (int i = 0; i < n_; ++i) {
    minus1_.push_back(wrap(i - 1));
    plus1_.push_back(wrap(i + 1));
    minus2_.push_back(wrap(i - 2));
    plus2_.push_back(wrap(i + 2));
  }
}

Eigen::Vector2d StableFluidGrid::sampleCells(const std::vector<Eigen::Vector2d>& field, double gx,
                                             double gz) const {
  const double fx = wrapInto(gx, n_), fz = wrapInto(gz, n_);
  const int i = int(fx), j = int(fz);
  const double tx = fx - i, tz = fz - j;
  const size_t row0 = size_t(j) * n_, row1 = size_t(plus1_[j]) * n_;
  const Eigen::Vector2d& v00 = field[row0 + i];
  const Eigen::Vector2d& v10 = field[row0 + plus1_[i]];
  const Eigen::Vector2d& v01 = field[row1 + i];
  const Eigen::Vector2d& v11 = field[row1 + plus1_[i]];
  return (1 - tz) * ((1 - tx) * v00 + tx * v10) + tz * ((1 - tx) * v01 + tx * v11);
}

Eigen::Vector2d StableFluidGrid::sample(double xMeters, double zMeters) const {
  return sampleCells(velocity_, xMeters / h_, zMeters / h_);
}

void StableFluidGrid::advect(double dtSeconds) {
  scratch_ = velocity_;
  const double cellsPerMeter = dtSeconds / h_;
  for (int j = 0; j < n_; ++j)
    for (int i = 0; i < n_; ++i) {
      const Eigen::Vector2d& v = scratch_[size_t(j) * n_ + i];
      velocity_[size_t(j) * n_ + i] =
          sampleCells(scratch_, i - cellsPerMeter * v.x(), j - cellsPerMeter * v.y());
    }
}

void StableFluidGrid::diffuse(double viscositySquareMetersPerSecond, double dtSeconds) {
  const double a = std::max(0.0, viscositySquareMetersPerSecond) * dtSeconds / (h_ * h_);
  if (a == 0.0) return;
  scratch_ = velocity_;
  // Each update is a convex combination of the old value and four neighbours: bounded for any a.
  const double weight = 1.0 / (1.0 + 4.0 * a);
  auto& v = velocity_;
  for (int sweep = 0; sweep < kDiffusionSweeps; ++sweep)
    for (int j = 0; j < n_; ++j) {
      const size_t row = size_t(j) * n_, down = size_t(minus1_[j]) * n_,
                   up = size_t(plus1_[j]) * n_;
      for (int i = 0; i < n_; ++i)
        v[row + i] = weight * (scratch_[row + i] + a * (v[row + minus1_[i]] + v[row + plus1_[i]] +
                                                        v[down + i] + v[up + i]));
    }
}

void StableFluidGrid::divergenceInto(std::vector<double>& out) const {
  const auto& v = velocity_;
  for (int j = 0; j < n_; ++j) {
    const size_t row = size_t(j) * n_, down = size_t(minus1_[j]) * n_, up = size_t(plus1_[j]) * n_;
    for (int i = 0; i < n_; ++i)
      out[row + i] =
          (v[row + plus1_[i]].x() - v[row + minus1_[i]].x() + v[up + i].y() - v[down + i].y()) /
          (2.0 * h_);
  }
}

void StableFluidGrid::project() {
  divergenceInto(divergence_);
  // Central divergence of a central gradient is the Laplacian with neighbours two nodes away:
  // four decoupled periodic grids of m = n / 2 nodes a side (n is even), each coloured
  // red-black by (i / 2 + j / 2), so SOR with Young's optimal factor for the Jacobi radius
  // (1 + cos(2 pi / m)) / 2 converges at its best rate (about 0.57 per sweep for n = 32: 40
  // sweeps cut the divergence by about 1e-8). The periodic system is singular but consistent
  // (the divergence sums to 0 on each subgrid) and only differences of p are used.
  const double jacobiRadius = 0.5 * (1.0 + std::cos(2.0 * M_PI / (n_ / 2)));
  const double omega = 2.0 / (1.0 + std::sqrt(1.0 - jacobiRadius * jacobiRadius));
  const double h2 = h_ * h_;
  std::fill(pressure_.begin(), pressure_.end(), 0.0);
  auto& p = pressure_;
  for (int sweep = 0; sweep < kPressureSweeps; ++sweep)
    for (int colour = 0; colour < 2; ++colour)
      for (int j = 0; j < n_; ++j) {
        const size_t row = size_t(j) * n_, down = size_t(minus2_[j]) * n_,
                     up = size_t(plus2_[j]) * n_;
        // Nodes 2k and 2k + 1 of this colour: k of parity colour ^ (j / 2).
        for (int i = 2 * (colour ^ ((j / 2) & 1)); i < n_; i += (i % 2 ? 3 : 1)) {
          const double gaussSeidel =
              0.25 * (p[row + minus2_[i]] + p[row + plus2_[i]] + p[down + i] + p[up + i] -
                      4.0 * h2 * divergence_[row + i]);
          p[row + i] += omega * (gaussSeidel - p[row + i]);
        }
      }
  for (int j = 0; j < n_; ++j) {
    const size_t row = size_t(j) * n_, down = size_t(minus1_[j]) * n_, up = size_t(plus1_[j]) * n_;
    for (int i = 0; i < n_; ++i)
      velocity_[row + i] -=
          Eigen::Vector2d(p[row + plus1_[i]] - p[row + minus1_[i]], p[up + i] - p[down + i]) /
          (2.0 * h_);
  }
}

void StableFluidGrid::clampMagnitude(double maxMetersPerSecond) {
  for (Eigen::Vector2d& v : velocity_) {
    const double norm = v.norm();
    if (norm > maxMetersPerSecond) v *= maxMetersPerSecond / norm;
  }
}

double StableFluidGrid::maxDivergence() const {
  std::vector<double> divergence(velocity_.size());
  divergenceInto(divergence);
  double largest = 0.0;
  for (double d : divergence) largest = std::max(largest, std::abs(d));
  return largest;
}

WindField::WindField(const WindSettings& settings)
    : settings_(settings), fluid_(settings.gridSize, settings.cellSizeMeters) {
  settings_.gustiness = std::clamp(settings_.gustiness, 0.0, 1.0);
  settings_.turbulence = std::clamp(settings_.turbulence, 0.0, 1.0);
  settings_.gustPeriodSeconds = std::max(settings_.gustPeriodSeconds, 1e-3);
  CounterRng rng(settings_.seed, kGustStream);
  for (double& phase : gustPhaseRadians_) phase = 2.0 * M_PI * rng.uniform();
  setBase(settings_.speedMetersPerSecond, settings_.directionDeg);
  gustNow_ = gustFactor(0.0);
}

void WindField::setBase(double speedMetersPerSecond, double directionDeg) {
  settings_.speedMetersPerSecond = std::max(0.0, speedMetersPerSecond);
  settings_.directionDeg = directionDeg;
  const double d = directionDeg * M_PI / 180.0;
  baseXZ_ = settings_.speedMetersPerSecond * Eigen::Vector2d(std::cos(d), -std::sin(d));
}

void WindField::startAt(double tSeconds, uint64_t step) {
  timeSeconds_ = tSeconds;
  step_ = step;
  gustNow_ = gustFactor(tSeconds);
  const double tile = fluid_.tileMeters();
  const Eigen::Vector2d drift = baseXZ_ * gustIntegral(tSeconds);
  frameOffsetMeters_ = {wrapInto(drift.x(), tile), wrapInto(drift.y(), tile)};
}

double WindField::gustFactor(double tSeconds) const {
  double sum = 0.0;
  for (size_t k = 0; k < kGustWeight.size(); ++k)
    sum += kGustWeight[k] *
           std::sin(2.0 * M_PI * kGustHarmonic[k] * tSeconds / settings_.gustPeriodSeconds +
                    gustPhaseRadians_[k]);
  return 1.0 + settings_.gustiness * sum;
}

double WindField::gustIntegral(double tSeconds) const {
  double sum = 0.0;
  for (size_t k = 0; k < kGustWeight.size(); ++k) {
    const double omega = 2.0 * M_PI * kGustHarmonic[k] / settings_.gustPeriodSeconds;
    sum += kGustWeight[k] / omega *
           (std::cos(gustPhaseRadians_[k]) - std::cos(omega * tSeconds + gustPhaseRadians_[k]));
  }
  return tSeconds + settings_.gustiness * sum;
}

double WindField::perturbationRms() const {
  return settings_.turbulence * settings_.speedMetersPerSecond;
}

double WindField::maxSpeedMetersPerSecond() const {
  return baseXZ_.norm() * (1.0 + settings_.gustiness) + kClampOverRms * perturbationRms();
}

void WindField::addForcing(double dtSeconds) {
  // Exact Ornstein–Uhlenbeck update v' = v e^(-dt/tau) + rms sqrt(1 - e^(-2 dt/tau)) xi, with
  // xi a field of random swirls of unit mean square, so the RMS settles at `rms` for any dt.
  const double tau = settings_.gustPeriodSeconds;
  const double decay = std::exp(-dtSeconds / tau);
  const double kick = perturbationRms() * std::sqrt(-std::expm1(-2.0 * dtSeconds / tau));
  const int n = fluid_.size();
  const double h = fluid_.cellSizeMeters(), tile = fluid_.tileMeters();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) fluid_.at(i, j) *= decay;
  if (kick == 0.0) return;
  CounterRng rng(settings_.seed, step_);
  for (int k = 0; k < kSwirlsPerStep; ++k) {
    const Eigen::Vector2d center(tile * rng.uniform(), tile * rng.uniform());
    // Radius tile/16..tile/8: at half a tile the swirl is below 3e-3 of its peak, so wrapping the
    // offset to the nearest image keeps it periodic and smooth.
    const double radius = tile * (1.0 + rng.uniform()) / 16.0;
    const double sign = rng.uniform() < 0.5 ? -1.0 : 1.0;
    // A swirl (-dz, dx) / r0 exp((1 - r^2/r0^2) / 2) has mean square pi e r0^2 / tile^2 over the
    // tile; this weight makes the sum of the swirls unit mean square.
    const double weight = sign * kick * tile / (radius * std::sqrt(kSwirlsPerStep * M_PI * M_E));
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double dx = nearestImage(i * h - center.x(), tile);
        const double dz = nearestImage(j * h - center.y(), tile);
        const double s = (dx * dx + dz * dz) / (radius * radius);
        fluid_.at(i, j) += weight * std::exp(0.5 * (1.0 - s)) / radius * Eigen::Vector2d(-dz, dx);
      }
  }
}

void WindField::advance(double dtSeconds) {
  if (!(dtSeconds >= 0.0) || !std::isfinite(dtSeconds))
    throw Error("wind: the time step must be finite and >= 0");
  if (dtSeconds == 0.0) return;
  addForcing(dtSeconds);
  fluid_.advect(dtSeconds);
  fluid_.diffuse(settings_.viscositySquareMetersPerSecond, dtSeconds);
  fluid_.project();
  fluid_.clampMagnitude(kClampOverRms * perturbationRms());
  // The fluid's frame drifts with the base wind times the gusts, integrated exactly.
  const double tile = fluid_.tileMeters();
  const double drift = gustIntegral(timeSeconds_ + dtSeconds) - gustIntegral(timeSeconds_);
  frameOffsetMeters_ += baseXZ_ * drift;
  frameOffsetMeters_ = {wrapInto(frameOffsetMeters_.x(), tile),
                        wrapInto(frameOffsetMeters_.y(), tile)};
  timeSeconds_ += dtSeconds;
  gustNow_ = gustFactor(timeSeconds_);
  ++step_;
}

Eigen::Vector3d WindField::velocityAt(double xMeters, double zMeters) const {
  const Eigen::Vector2d v = baseXZ_ * gustNow_ + fluid_.sample(xMeters - frameOffsetMeters_.x(),
                                                               zMeters - frameOffsetMeters_.y());
  return {v.x(), 0.0, v.y()};
}

}  // namespace pluvia::rain
