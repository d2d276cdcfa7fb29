#pragma once
// Dense per-frame depth from SfM's sparse points, guided by the frame.
//
// Method (parameters in DensifyOptions):
//  1. The points the frame sees are projected with its pose; each splats its inverse depth onto
//     one pixel (samples landing on the same pixel average). Inverse depth is interpolated, not
//     depth: it is what varies linearly across a plane in the image, and it keeps far samples
//     from dominating near ones. Samples whose inverse depth disagrees with the median of their
//     nearest samples in the image are dropped first (rejectDepthOutliers): one bad SfM point
//     otherwise raises a spike over every Delaunay triangle it belongs to.
//  2. A prior with no holes: linear interpolation of inverse depth over the Delaunay triangulation
//     of the samples (exact on any plane: inverse depth is affine in the image over a plane);
//     outside the samples' convex hull, push-pull (Gortler et al. 1996, a normalized-convolution
//     pyramid) extends the triangulated field, continuously across the hull's outline.
//     With a ground camera (DensifyOptions::groundCamera), the ground plane y = 0 bounds the
//     depth: a ray that meets the ground meets nothing farther, since everything stands on it.
//     The ground is first corrected by the samples lying on it (the ratio of their inverse depth
//     to the ground's, within groundMaxCorrection of 1, extended by push-pull: a camera height
//     or tilt slightly off). Outside the samples' hull, and inside it beyond about
//     groundBlendSpacings sample spacings (blended smoothly), the prior is never farther than
//     that ground: where SfM has no points (the blurred ground just in front of the camera) the
//     ground's depth replaces extrapolation of the farther samples, while a nearer extrapolated
//     surface (a wall reaching the bottom of the frame) is kept.
//  3. Edge-aware correction: the samples' residuals against that prior (zero on planes, large
//     where a triangle spans a depth step) are spread by a confidence-weighted fast global
//     smoother (Min et al. 2014, cv::ximgproc::fastGlobalSmootherFilter) guided by the frame's
//     grey levels: FGS(w * residual) / FGS(w + priorWeight), added to the prior. The residual
//     spreads within regions bounded by image edges and fades to the prior far from samples.
//     (Smoothing depth itself would bias every ramp wherever texture edges cut the kernel.)
//  4. Sky (+infinity, pluvia's sky depth, rather than an extrapolated guess): where
//     geometry/sky_mask.h finds it, seeded far from the samples and grown up to near them.
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "geometry/camera.h"
#include "geometry/sky_mask.h"
#include "image/image.h"

namespace pluvia::sfm {

struct SparseDepthSample {
  double xPx = 0.0;  // pixel position, pixel centres at +0.5
  double yPx = 0.0;
  double depthMeters = 0.0;  // z-depth along the optical axis
};

// Projects the points (all, or those indexed by `subset`) with `camera`, keeping those with
// positive depth inside the image.
std::vector<SparseDepthSample> projectSparsePoints(const Camera& camera,
                                                   const std::vector<Eigen::Vector3d>& pointsMeters,
                                                   const std::vector<int>* subset = nullptr);

// Drops the samples whose inverse depth v disagrees with their `neighbours` nearest samples in
// the image, that is, all three of: |v - m| > maxRelativeDeviation * m, m the neighbours' median;
// fewer than two neighbours within maxRelativeDeviation * v of v (a small foreground object or
// the near side of a depth step keeps its samples); and v off the plane (affine function of the
// image position) robustly fitted to the neighbours by more than max(maxRelativeDeviation * p,
// 3 robust standard deviations of the neighbours about it), p the plane's value (a steep ramp,
// such as the ground just below the horizon, sampled from one side, keeps its samples). With
// fewer than neighbours + 1 samples, or neighbours <= 0, all are kept.
std::vector<SparseDepthSample> rejectDepthOutliers(const std::vector<SparseDepthSample>& samples,
                                                   int neighbours = 8,
                                                   double maxRelativeDeviation = 0.25);

struct DensifyOptions {
  double smootherLambda = 300.0;   // fast global smoother strength (larger: smoother, wider)
  double smootherSigmaColor = 10;  // guide contrast (8-bit grey levels) that counts as an edge
  double priorWeight = 0.02;       // how fast residuals fade to the prior away from samples

  // Outlier samples (rejectDepthOutliers): 0 neighbours keeps every sample. 0.25 in inverse
  // depth is a depth off by more than -20 % / +33 %: well beyond SfM's few-% noise on points
  // seen from several views, well below the factor of 2 or more of a mismatched track.
  int outlierNeighbours = 8;
  double outlierMaxRelativeDeviation = 0.25;

  // The frame's metric camera in a world whose ground is y = 0 with +Y up (what sfm_poses
  // produces with a camera-height scale hint). Without it there is no ground bound and no
  // horizon test for the sky.
  std::optional<Camera> groundCamera;
  double groundMaxDistanceMeters = 100.0;  // rays meeting the ground farther away are not bound
  // Samples whose inverse depth is within this ratio of the ground's correct the ground camera.
  double groundMaxCorrection = 0.3;
  // Inside the samples' hull, the bound takes over this many median sample spacings from them.
  double groundBlendSpacings = 2.0;

  bool detectSky = true;
  SkyMaskSettings sky;
};

// Metric z-depth, width * height row-major (the guide's size), +infinity for sky. `guide` is the
// frame: 8-bit or float (linear 0..1), 1, 3 or 4 channels. With no samples everything is +inf.
std::vector<float> densifySparseDepth(const std::vector<SparseDepthSample>& samples,
                                      const cv::Mat& guide, const DensifyOptions& options = {});
// The same with a pluvia frame (linear float RGBA) as the guide.
std::vector<float> densifySparseDepth(const std::vector<SparseDepthSample>& samples,
                                      const Image& frame, const DensifyOptions& options = {});

}  // namespace pluvia::sfm
