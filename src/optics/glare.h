#pragma once
// Glare: the veil a bright source spreads over the picture, as the eye sees it. The kernel is
// the CIE 2002 general disability glare equation (CIE 146:2002, Vos and van den Berg), the
// equivalent veiling luminance per unit of glare illuminance at the eye, theta in degrees:
//   L_veil / E_glare = 10 / theta^3 + (5 / theta^2 + 0.1 p / theta) (1 + (A / 62.5)^4) + 0.0025 p
// in 1/sr, valid from 0.1 to 100 deg; A the observer's age (25 here), p the eye's pigmentation
// (0.5: brown; 0 very dark, 1 blue-green). A source of radiance L in a pixel of solid angle
// Omega gives E_glare = L Omega, so a pixel at angle theta from it receives
// L Omega PSF(theta): the kernel weight of one pixel is PSF(theta) Omega (Omega = 1 / f^2 near
// the axis, cos^3 theta / f^2 off it). The part scattered (about 25 % of the light within 20
// deg for A = 25) leaves the source's own pixel, so the kernel sums to 1: energy is moved, not
// made. Under 0.1 deg (the formula's lower bound) the kernel is held at PSF(0.1 deg).
//
// Fast form (GlarePyramid): the kernel as a sum of pyramid blurs, sum_j a_j up(D_j) + c_j
// up(G(D_j)), D_j the source reduced j times (the binomial [1 4 6 4 1] / 16 filter, every other
// pixel kept) and G a Gaussian of 1 px at that level (each about half an octave apart, from 1 px
// to the frame's size), collapsed coarse to fine (zeros between the pixels, the same filter).
// Zeros past the frame's edges: light scattered out of the frame is lost, as with the true
// kernel. The weights are fitted (non-negative least squares, relative error of the
// radial profile) to the true kernel using the measured impulse responses of those very blurs,
// so the fit includes what the pyramid's own filters do. `pluvia report lights` measures it
// against direct convolution with the true kernel (glareReference).
#include <vector>

#include "image/image.h"

namespace pluvia::optics {

constexpr double kGlareAgeYears = 25.0;
constexpr double kGlarePigment = 0.5;
constexpr double kGlareMinDeg = 0.1;  // the formula's lower bound: the kernel is flat inside

// The CIE 2002 general disability glare PSF at `thetaDeg` (clamped to [0.1, 100] deg), 1/sr.
double cieGlarePsf(double thetaDeg, double ageYears = kGlareAgeYears,
                   double pigment = kGlarePigment);

// The true kernel's weight of a pixel `radiusPx` from the source's pixel (radiusPx > 0) for a
// focal length of `focalPx`: PSF(atan(r / f)) cos^3(theta) / f^2.
double glareKernelWeight(double radiusPx, double focalPx);

// The image's RGB convolved with the true kernel, sampled per pixel out to the frame's own size
// in every direction (a source anywhere reaches every pixel) and summing to 1 (the source's own
// pixel keeps 1 minus the rest), light past the edges lost; by FFT. The reference.
Image glareReference(const Image& source, double focalPx);

class GlarePyramid {
 public:
  // Fits the weights for frames of width x height and `focalPx` (a few tens of ms at 1080p).
  GlarePyramid(int width, int height, double focalPx);

  // `source` (RGB of an Image, alpha ignored) convolved with the fitted kernel (alpha 1); the sum
  // is kept but for the light scattered past the frame's edges.
  Image convolve(const Image& source) const;
  // The same on CV_32FC3.
  cv::Mat convolve(const cv::Mat& rgb) const;

  int width() const { return width_; }
  int height() const { return height_; }
  double focalPx() const { return focalPx_; }
  int levels() const { return levels_; }
  // The share of the light the true kernel scatters out of the source's pixel within the
  // frame's size, and the share the fitted one does.
  double scatteredFraction() const { return trueScattered_; }
  double fittedScatteredFraction() const { return fittedScattered_; }
  // The fit's radial profile against the true one: radii (px) and the mean kernel weight over
  // an annulus around each, for the tests and the report.
  std::vector<double> profileRadiiPx() const { return radiiPx_; }
  std::vector<double> fittedProfile() const { return fittedProfile_; }
  std::vector<double> trueProfile() const { return trueProfile_; }

 private:
  int width_, height_;
  double focalPx_;
  int levels_ = 0;
  // Per level j = 0..levels: the reduced source's weight (a_j; a_0 the unscattered part) and
  // its blurred copy's (c_j).
  std::vector<double> plainWeight_, blurredWeight_;
  double trueScattered_ = 0.0, fittedScattered_ = 0.0;
  std::vector<double> radiiPx_, fittedProfile_, trueProfile_;
};

}  // namespace pluvia::optics
