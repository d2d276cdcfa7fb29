#pragma once
// Unsteady horizontal wind (Mizukami et al. section 4.2): a base wind whose strength varies in
// gusts, plus a 2-D perturbation solved with Stam's Stable Fluids (1999) on a periodic grid that
// tiles the XZ plane (the world is +Y up), so the field is defined everywhere.
//
// The perturbation lives in a frame carried by the (gusting) base wind: swirls drift downwind
// exactly instead of being smeared by advecting them through the grid, and the solver only
// advects the perturbation by itself. Its forcing is an Ornstein–Uhlenbeck process in time
// (decay exp(-dt / gust period), seeded random swirl kicks scaled so the stationary RMS is
// turbulence * base speed whatever the step), so the statistics do not depend on dt.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace pluvia::rain {

struct WindSettings {
  double speedMetersPerSecond = 0.0;
  double directionDeg = 0.0;  // 0 = +X, 90 = -Z: velocity = speed (cos d, 0, -sin d)
  double gustiness = 0.0;     // 0..1: relative amplitude of the gusts
  double gustPeriodSeconds = 4.0;
  double turbulence = 0.0;  // 0..1: RMS of the fluid perturbation over the base speed; 0 = none
  int gridSize = 32;        // nodes per side: made even, clamped to [8, 512]
  double cellSizeMeters = 2.0;
  double viscositySquareMetersPerSecond = 0.2;  // eddy viscosity of the perturbation
  uint64_t seed = 1;
};

// A periodic square grid of 2-D velocities (x, z) at its nodes, node (i, j) at (i h, j h),
// with the steps of Stable Fluids. Every step is bounded for any dt.
class StableFluidGrid {
 public:
  // size is clamped to [8, 512] and made even (see project()).
  StableFluidGrid(int size, double cellSizeMeters);

  int size() const { return n_; }
  double cellSizeMeters() const { return h_; }
  double tileMeters() const { return n_ * h_; }
  // Any integer indices, wrapped.
  Eigen::Vector2d& at(int i, int j) { return velocity_[index(i, j)]; }
  const Eigen::Vector2d& at(int i, int j) const { return velocity_[index(i, j)]; }
  // Bilinear and periodic, at a point in metres.
  Eigen::Vector2d sample(double xMeters, double zMeters) const;

  // Semi-Lagrangian self-advection: each node takes the velocity found dt back along itself.
  void advect(double dtSeconds);
  // Implicit diffusion (I - nu dt Laplacian) v' = v, a fixed number of Gauss–Seidel sweeps.
  void diffuse(double viscositySquareMetersPerSecond, double dtSeconds);
  // Removes the gradient part: solves Laplacian p = div v with red-black SOR (fixed sweeps)
  // and subtracts grad p. The Laplacian is the one central differences compose to, so a
  // converged solve leaves exactly zero discrete divergence.
  void project();
  void clampMagnitude(double maxMetersPerSecond);
  // Largest |div v| over the nodes, central differences, 1/s.
  double maxDivergence() const;

 private:
  size_t index(int i, int j) const { return size_t(wrap(j) * n_ + wrap(i)); }
  int wrap(int i) const { return ((i % n_) + n_) % n_; }
  Eigen::Vector2d sampleCells(const std::vector<Eigen::Vector2d>& field, double gx,
                              double gz) const;
  void divergenceInto(std::vector<double>& out) const;

  int n_;
  double h_;
  // Wrapped neighbour indices along either axis: i - 1, i + 1, i - 2, i + 2.
  std::vector<int> minus1_, plus1_, minus2_, plus2_;
  std::vector<Eigen::Vector2d> velocity_, scratch_;
  std::vector<double> pressure_, divergence_;
};

class WindField {
 public:
  explicit WindField(const WindSettings& settings);

  // Changes the base wind from now on (a ramped speed or direction); the fluid is kept.
  void setBase(double speedMetersPerSecond, double directionDeg);
  // Sets the clock to `tSeconds` and the forcing to its `step`-th kicks, as if the field had
  // advanced that far (the gusts and the fluid frame's drift are closed forms of the time; the
  // fluid itself starts at rest and takes a gust period or so to settle).
  void startAt(double tSeconds, uint64_t step);

  // One Stable Fluids step: forcing, advection, diffusion, projection, then a clamp of the
  // perturbation to 4 times its RMS as a last guard. dt = 0 changes nothing; dt must be finite
  // and >= 0.
  void advance(double dtSeconds);

  // The wind at a point at the current time; y is 0.
  Eigen::Vector3d velocityAt(double xMeters, double zMeters) const;
  // Upper bound of |velocityAt| anywhere, now and later at this base wind.
  double maxSpeedMetersPerSecond() const;

  double timeSeconds() const { return timeSeconds_; }
  // Smooth, >= 0, mean 1: 1 + gustiness * (a weighted sum of three sinusoids, seeded phases).
  double gustFactor(double tSeconds) const;
  double gustIntegral(double tSeconds) const;  // integral of gustFactor from 0 to t
  double tileMeters() const { return fluid_.tileMeters(); }
  const StableFluidGrid& fluid() const { return fluid_; }

 private:
  double perturbationRms() const;
  void addForcing(double dtSeconds);

  WindSettings settings_;
  Eigen::Vector2d baseXZ_;  // m/s
  StableFluidGrid fluid_;
  double timeSeconds_ = 0.0;
  double gustNow_ = 1.0;
  uint64_t step_ = 0;
  Eigen::Vector2d frameOffsetMeters_ = Eigen::Vector2d::Zero();  // where the fluid frame drifted
  std::array<double, 3> gustPhaseRadians_;
};

}  // namespace pluvia::rain
