#include "io/ycbcr_frame.h"

#include <algorithm>

#include <fmt/format.h>
#include <opencv2/core/utility.hpp>

#include "util/error.h"

namespace pluvia {
namespace {

// One row's samples (RGBA, alpha too: a stride-1 loop, which the compiler vectorises) clamped to
// [0, 1] (NaN -> 0: std::min passes NaN on, std::max(0, NaN) is 0) and rounded to the nearest
// 16-bit code, ties up, as the 16-bit TIFF frames a farm chunk writes hold them: a movie
// assembled from those gets the very Y'CbCr of a one-machine render (the farm test compares
// the files).
void quantizeRow(const float* rgba, int width, float* out) {
  const size_t samples = static_cast<size_t>(width) * 4;
  for (size_t i = 0; i < samples; ++i) {
    const float unit = std::max(0.0f, std::min(rgba[i], 1.0f));
    out[i] = static_cast<float>(static_cast<int>(unit * 65535.0f + 0.5f)) * (1.0f / 65535.0f);
  }
}

// A code in [0, 255] rounded to the nearest integer.
inline uint8_t rounded(float code) {
  return static_cast<uint8_t>(static_cast<int>(code + 0.5f));
}

struct Weights {
  float kr, kg, kb;
};

// Y' codes of one row of `width` RGBA pixels, quantised.
void lumaRow(const float* rgba, int width, const Weights& k, uint8_t* luma) {
  for (int x = 0; x < width; ++x) {
    const float* p = rgba + static_cast<size_t>(x) * 4;
    luma[x] = rounded(16.0f + 219.0f * (k.kr * p[0] + k.kg * p[1] + k.kb * p[2]));
  }
}

// Adds the R', G', B' of each pixel pair of one row to sums[c][cx] (c = 0, 1, 2 planes of
// `pairs` values); an odd last pixel counts twice, as the repeated column it stands for.
void addPairSums(const float* rgba, int width, int pairs, float* sums) {
  float* r = sums;
  float* g = sums + pairs;
  float* b = sums + 2 * static_cast<size_t>(pairs);
  const int fullPairs = width / 2;
  for (int cx = 0; cx < fullPairs; ++cx) {
    const float* p = rgba + static_cast<size_t>(cx) * 8;
    r[cx] += p[0] + p[4];
    g[cx] += p[1] + p[5];
    b[cx] += p[2] + p[6];
  }
  if (fullPairs < pairs) {
    const float* p = rgba + static_cast<size_t>(width - 1) * 4;
    r[fullPairs] += 2.0f * p[0];
    g[fullPairs] += 2.0f * p[1];
    b[fullPairs] += 2.0f * p[2];
  }
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
  const Weights k{matrix.kr, 1.0f - matrix.kr - matrix.kb, matrix.kb};
  // Codes from the colour differences B' - E'y and R' - E'y (ITU-R BT.709 section 3), of the
  // mean of the pixels a chroma sample covers.
  const float blueScale = 224.0f / (2.0f * (1.0f - k.kb)),
              redScale = 224.0f / (2.0f * (1.0f - k.kr));
  const float meanOfSums = 1.0f / static_cast<float>(2 * rowsPerChroma);
  uint8_t* luma = planes.data();
  uint8_t* cb = luma + lumaSize;
  uint8_t* cr = cb + chromaSize;
  cv::parallel_for_(cv::Range(0, chromaHeight), [&](const cv::Range& rows) {
    std::vector<float> sums(static_cast<size_t>(chromaWidth) * 3);  // R', G', B' planes
    std::vector<float> row(static_cast<size_t>(image.width) * 4);   // quantised
    const float* r = sums.data();
    const float* g = r + chromaWidth;
    const float* b = g + chromaWidth;
    for (int cy = rows.start; cy < rows.end; ++cy) {
      std::fill(sums.begin(), sums.end(), 0.0f);
      for (int y = cy * rowsPerChroma; y < (cy + 1) * rowsPerChroma; ++y) {
        quantizeRow(image.pixel(0, std::min(y, image.height - 1)), image.width, row.data());
        uint8_t* lumaOut = luma + static_cast<size_t>(y) * encodedWidth;
        lumaRow(row.data(), image.width, k, lumaOut);
        if (encodedWidth > image.width) lumaOut[image.width] = lumaOut[image.width - 1];
        addPairSums(row.data(), image.width, chromaWidth, sums.data());
      }
      uint8_t* cbRow = cb + static_cast<size_t>(cy) * chromaWidth;
      uint8_t* crRow = cr + static_cast<size_t>(cy) * chromaWidth;
      for (int cx = 0; cx < chromaWidth; ++cx) {
        const float ey = (k.kr * r[cx] + k.kg * g[cx] + k.kb * b[cx]) * meanOfSums;
        cbRow[cx] = rounded(128.0f + blueScale * (b[cx] * meanOfSums - ey));
        crRow[cx] = rounded(128.0f + redScale * (r[cx] * meanOfSums - ey));
      }
    }
  });
}

}  // namespace pluvia
