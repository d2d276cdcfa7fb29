#include "io/ycbcr_frame.h"

#include <algorithm>

#include <fmt/format.h>
#include <opencv2/core/utility.hpp>

#include "util/error.h"

namespace pluvia {
namespace {

// NaN -> 0.
inline float clamped(float v) {
  return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
}

// A code in [0, 255] rounded to the nearest integer.
inline uint8_t rounded(float code) {
  return static_cast<uint8_t>(code + 0.5f);
}

}  // namespace

YcbcrMatrix ycbcrMatrix(const std::string& ffmpegName, const std::string& path) {
  if (ffmpegName.empty() || ffmpegName == "bt709") return {0.2126f, 0.0722f};
  if (ffmpegName == "bt2020nc") return {0.2627f, 0.0593f};
  throw Error(fmt::format("no Y'CbCr matrix named '{}' for the movie {} (known: bt709, bt2020nc)",
                          ffmpegName, path),
              {"write", {}, path});
}

void packYcbcr8(const Image& image, int encodedWidth, int encodedHeight, bool halfHeightChroma,
                const YcbcrMatrix& matrix, std::vector<uint8_t>& planes) {
  const int chromaWidth = encodedWidth / 2;
  const int rowsPerChroma = halfHeightChroma ? 2 : 1;
  const int chromaHeight = encodedHeight / rowsPerChroma;
  const size_t lumaSize = static_cast<size_t>(encodedWidth) * encodedHeight;
  const size_t chromaSize = static_cast<size_t>(chromaWidth) * chromaHeight;
  planes.resize(lumaSize + 2 * chromaSize);
  const float kr = matrix.kr, kb = matrix.kb, kg = 1.0f - kr - kb;
  // Codes from E'y and from the colour differences B' - E'y, R' - E'y (BT.709 section 3).
  const float lumaScale = 219.0f, blueScale = 224.0f / (2.0f * (1.0f - kb)),
              redScale = 224.0f / (2.0f * (1.0f - kr));
  const float chromaMean = 1.0f / static_cast<float>(2 * rowsPerChroma);
  uint8_t* luma = planes.data();
  uint8_t* cb = luma + lumaSize;
  uint8_t* cr = cb + chromaSize;
  cv::parallel_for_(cv::Range(0, chromaHeight), [&](const cv::Range& rows) {
    std::vector<float> sums(static_cast<size_t>(chromaWidth) * 3);  // R', G', B' per chroma column
    for (int cy = rows.start; cy < rows.end; ++cy) {
      std::fill(sums.begin(), sums.end(), 0.0f);
      for (int k = 0; k < rowsPerChroma; ++k) {
        const int y = cy * rowsPerChroma + k;
        const float* row = image.pixel(0, std::min(y, image.height - 1));
        uint8_t* lumaRow = luma + static_cast<size_t>(y) * encodedWidth;
        for (int cx = 0; cx < chromaWidth; ++cx) {
          float* sum = sums.data() + static_cast<size_t>(cx) * 3;
          for (int x = 2 * cx; x < 2 * cx + 2; ++x) {
            const float* p = row + static_cast<size_t>(std::min(x, image.width - 1)) * 4;
            const float r = clamped(p[0]), g = clamped(p[1]), b = clamped(p[2]);
            lumaRow[x] = rounded(16.0f + lumaScale * (kr * r + kg * g + kb * b));
            sum[0] += r, sum[1] += g, sum[2] += b;
          }
        }
      }
      uint8_t* cbRow = cb + static_cast<size_t>(cy) * chromaWidth;
      uint8_t* crRow = cr + static_cast<size_t>(cy) * chromaWidth;
      for (int cx = 0; cx < chromaWidth; ++cx) {
        const float* sum = sums.data() + static_cast<size_t>(cx) * 3;
        const float r = sum[0] * chromaMean, g = sum[1] * chromaMean, b = sum[2] * chromaMean;
        const float ey = kr * r + kg * g + kb * b;
        cbRow[cx] = rounded(128.0f + blueScale * (b - ey));
        crRow[cx] = rounded(128.0f + redScale * (r - ey));
      }
    }
  });
}

}  // namespace pluvia
