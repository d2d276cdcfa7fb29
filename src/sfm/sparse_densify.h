#pragma once
// Dense per-frame depth from SfM's sparse points, guided by the frame.
//
// Method (parameters in DensifyOptions):
//  1. The points the frame sees are projected with its pose; each splats its inverse depth onto
//     one pixel (samples landing on the same pixel average). Inverse depth is interpolated, not
//     depth: it is what varies linearly across a plane in the image, and it keeps far samples
//     from dominating near ones.
//  2. A prior with no holes: linear interpolation of inverse depth over the Delaunay triangulation
//     of the samples (exact on any plane: inverse depth is affine in the image over a plane);
//     outside the samples' convex hull, push-pull (Gortler et al. 1996, a normalized-convolution
//     pyramid) extends it.
//  3. Edge-aware correction: the samples' residuals against that prior (zero on planes, large
//     where a triangle spans a depth step) are spread by a confidence-weighted fast global
//     smoother (Min et al. 2014, cv::ximgproc::fastGlobalSmootherFilter) guided by the frame's
//     grey levels: FGS(w * residual) / FGS(w + priorWeight), added to the prior. The residual
//     spreads within regions bounded by image edges and fades to the prior far from samples.
//     (Smoothing depth itself would bias every ramp wherever texture edges cut the kernel.)
//  4. Sky: pixels far from every sample (skyMinDistanceFraction of the diagonal), brighter than
//     the frame's median, with little texture (smoothed gradient below skyMaxGradient), and
//     connected to the top row through such pixels become +infinity (pluvia's sky depth) rather
//     than an extrapolated guess.
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "geometry/camera.h"
#include "image/image.h"

namespace pluvia {

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

struct DensifyOptions {
  double smootherLambda = 300.0;   // fast global smoother strength (larger: smoother, wider)
  double smootherSigmaColor = 10;  // guide contrast (8-bit grey levels) that counts as an edge
  double priorWeight = 0.02;       // how fast residuals fade to the prior away from samples
  bool detectSky = true;
  double skyMinDistanceFraction = 0.05;  // of the image diagonal, from the nearest sample
  double skyMaxGradient = 8.0;           // grey levels per pixel, smoothed over 9x9 pixels
};

// Metric z-depth, width * height row-major (the guide's size), +infinity for sky. `guide` is the
// frame: 8-bit or float (linear 0..1), 1, 3 or 4 channels. With no samples everything is +inf.
std::vector<float> densifySparseDepth(const std::vector<SparseDepthSample>& samples,
                                      const cv::Mat& guide, const DensifyOptions& options = {});
// The same with a pluvia frame (linear float RGBA) as the guide.
std::vector<float> densifySparseDepth(const std::vector<SparseDepthSample>& samples,
                                      const Image& frame, const DensifyOptions& options = {});

}  // namespace pluvia
