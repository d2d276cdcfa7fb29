#pragma once
// Resizing frames for proxy renders (quick looks at a reduced size).
#include "image/image.h"

namespace pluvia {

// The size of a width x height frame scaled by `scale`: each side rounded to the nearest pixel,
// at least 1.
cv::Size scaledSize(int width, int height, double scale);

// `image` resized to `size` with OpenCV's area filter (each output pixel the mean of the input
// pixels it covers, so shrinking does not alias). RGBA only: the result has no named planes,
// which suits frames just read (they carry none).
Image resizeArea(const Image& image, cv::Size size);

}  // namespace pluvia
