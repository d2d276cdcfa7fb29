#pragma once
// Image operations as free functions (OpenImageIO ImageBufAlgo style). All follow image.h's
// conventions: scene-linear float RGBA, straight alpha; alpha is left untouched.
#include <array>
#include <limits>

#include "image/image.h"
#include "image/luminance.h"

namespace pluvia::ops {

// Rec.709 luminance of a linear RGB triple.
inline float luminance(const float* rgb) {
  return rec709LuminanceFloat(rgb);
}

// Starik–Werman darkening: blend each pixel toward its luminance by `amount` (desaturation)
// and scale it by (1 - amount * strength). amount 0 is the identity. With `weight` (one value per
// pixel), pixel i takes amount * weight[i].
//   out = (1 - amount) * rgb + amount * Y, then * (1 - amount * darkening)
void darken(Image& image, float amount, float darkening, const float* weight = nullptr);

// Gaussian blur of RGB with standard deviation sigmaPx (pixels), reflecting at the border so the
// mean is preserved. sigma 0 is the identity.
void gaussianBlur(Image& image, float sigmaPx);

// The same blur mixed in by pixel: out = rgb + weight[i] * (blurred - rgb), RGB only, without a
// copy of the frame (each row is mixed as it is blurred).
void gaussianBlurToward(Image& image, float sigmaPx, const float* weight);

// Homogeneous fog: alpha = 1 - exp(-density * min(depth, maxDepthMeters)),
// out = alpha * fogRgb + (1 - alpha) * rgb, with depth the "depth" plane (metres). The sky
// (infinite depth) keeps its own colour and detail: it is already the airlight at infinity, so
// fog there tends toward the sky's own colour. maxDepthMeters bounds the path through the fog
// (the visibility distance). density 0 is the identity.
void fog(Image& image, float densityPerMeter, const std::array<float, 3>& fogRgb,
         float maxDepthMeters = std::numeric_limits<float>::infinity());

// Replaces NaN and infinite RGB values by 0 (documented input handling for EXR plates) and
// returns how many values were replaced. Neighbours are never read, so nothing spreads.
size_t replaceNonFinite(Image& image);

}  // namespace pluvia::ops
