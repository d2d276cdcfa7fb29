#pragma once
// Image-quality measures for comparing a result with its ground truth.
#include <opencv2/core.hpp>

namespace pluvia {

// Peak signal-to-noise ratio in dB over all channels, peak 1 (images in 0..1, CV_32F any
// channel count, same size). +infinity when the images are equal.
double psnrDb(const cv::Mat& result, const cv::Mat& truth);
// Structural similarity (Wang, Bovik, Sheikh, Simoncelli 2004): 11x11 Gaussian window,
// sigma 1.5, K1 = 0.01, K2 = 0.03, dynamic range 1; mean over pixels and channels. As in the
// authors' reference code the mean is over the windows that lie inside the image (a 5-pixel
// border is left out); an image smaller than 11x11 is averaged over all its pixels.
double ssim(const cv::Mat& result, const cv::Mat& truth);

}  // namespace pluvia
