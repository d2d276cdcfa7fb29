#pragma once
// Rec.709 luminance, the one weighting pluvia uses wherever it asks how bright a colour is: of
// scene-linear RGB, or of display-encoded values as a luma where a caller says so.
namespace pluvia {

inline constexpr double kRec709Red = 0.2126, kRec709Green = 0.7152, kRec709Blue = 0.0722;

// Of any triple indexable by 0, 1, 2 (float*, std::array, cv::Vec3f, Eigen), in double.
template <typename Rgb>
double rec709Luminance(const Rgb& rgb) {
  return kRec709Red * rgb[0] + kRec709Green * rgb[1] + kRec709Blue * rgb[2];
}

// The same in float, for per-pixel loops over float images.
inline float rec709LuminanceFloat(const float* rgb) {
  return float(kRec709Red) * rgb[0] + float(kRec709Green) * rgb[1] + float(kRec709Blue) * rgb[2];
}
static_assert(float(kRec709Red) == 0.2126f && float(kRec709Green) == 0.7152f &&
              float(kRec709Blue) == 0.0722f);

}  // namespace pluvia
