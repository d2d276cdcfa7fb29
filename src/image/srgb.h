#pragma once
// The sRGB transfer function (IEC 61966-2-1), for the places that need it outside the colour
// pipeline (which goes through OpenColorIO, image/color.h): feature images for matching, 8-bit
// previews in the reports, display codes for the rain measurements.
#include <cmath>

namespace pluvia {

// Linear to encoded, both 0..1; values outside are not clamped (the curve is continued).
inline double srgbEncode(double linear) {
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

// Encoded to linear.
inline double srgbDecode(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

}  // namespace pluvia
