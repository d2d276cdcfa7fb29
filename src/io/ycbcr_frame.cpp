#include "io/ycbcr_frame.h"

#include <algorithm>

#include <fmt/format.h>
#include <opencv2/core/utility.hpp>

#include "util/error.h"
#include "util/parallel.h"

namespace pluvia {
namespace {

// The codes Y'CbCr may use at `bits`: video range without its reserved codes (0 and 255 at 8
// bits, 0-3 and 1020-1023 at 10; ITU-R BT.709 section 4: 1 to 254, scaled by 2^(bits - 8)), so
// that super-whites and sub-blacks a plate held go out as the codes they came in as.
struct LegalCodes {
  float low, high;    // codes
  float lowE, highE;  // the R' = G' = B' whose Y' is the lowest and the highest code
};

LegalCodes legalCodes(int bits) {
  const float scale = static_cast<float>(1 << (bits - 8));
  const float low = scale, high = static_cast<float>((1 << bits) - 1) - scale;
  return {low, high, (low / scale - 16.0f) / 219.0f, (high / scale - 16.0f) / 219.0f};
}

// One row's samples (RGBA, alpha too: a stride-1 loop, which the compiler vectorises): R', G',
// B' clamped to those of the legal Y' codes, alpha to [0, 1], NaN as 0. Not quantised: a farm
// chunk's frames are float TIFF (farm/farm_job.h), so a movie assembled from them gets these very
// samples, and the very Y'CbCr of a one-machine render (the farm test compares the files).
void legalRow(const float* rgba, int width, const LegalCodes& legal, float* out) {
  const size_t samples = static_cast<size_t>(width) * 4;
  for (size_t i = 0; i < samples; ++i) {
    const bool alpha = i % 4 == 3;
    const float low = alpha ? 0.0f : legal.lowE, high = alpha ? 1.0f : legal.highE;
    const float value = rgba[i];
    out[i] = value == value ? std::max(low, std::min(value, high)) : 0.0f;
  }
}

// A code rounded to the nearest integer (codes are never negative).
template <class Sample>
inline Sample rounded(float code) {
  return static_cast<Sample>(static_cast<int>(code + 0.5f));
}

// A colour-difference code rounded and kept legal: a saturated colour beyond white can ask for
// one past them.
template <class Sample>
inline Sample legalRounded(float code, const LegalCodes& legal) {
  return rounded<Sample>(std::max(legal.low, std::min(code, legal.high)));
}

struct Weights {
  float kr, kg, kb;
};

// Y' codes of one row of `width` legal RGBA pixels; `scale` is 2^(bits - 8).
template <class Sample>
void lumaRow(const float* rgba, int width, const Weights& k, float scale, Sample* luma) {
  for (int x = 0; x < width; ++x) {
    const float* p = rgba + static_cast<size_t>(x) * 4;
    luma[x] = rounded<Sample>((16.0f + 219.0f * (k.kr * p[0] + k.kg * p[1] + k.kb * p[2])) * scale);
  }
}

// Adds the R', G', B' of the pixels each chroma sample of one row covers (`columns` of them, 1
// or 2) to sums[c][cx] (c = 0, 1, 2 planes of `samples` values); an odd last pixel of a pair
// counts twice, as the repeated column it stands for.
void addChromaSums(const float* rgba, int width, int columns, int samples, float* sums) {
  float* r = sums;
  float* g = sums + samples;
  float* b = sums + 2 * static_cast<size_t>(samples);
  if (columns == 1) {
    for (int cx = 0; cx < width; ++cx) {
      const float* p = rgba + static_cast<size_t>(cx) * 4;
      r[cx] += p[0];
      g[cx] += p[1];
      b[cx] += p[2];
    }
    return;
  }
  const int fullPairs = width / 2;
  for (int cx = 0; cx < fullPairs; ++cx) {
    const float* p = rgba + static_cast<size_t>(cx) * 8;
    r[cx] += p[0] + p[4];
    g[cx] += p[1] + p[5];
    b[cx] += p[2] + p[6];
  }
  if (fullPairs < samples) {
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

template <class Sample>
void packYcbcr(const Image& image, int encodedWidth, int encodedHeight, const YcbcrLayout& layout,
               const YcbcrMatrix& matrix, std::vector<Sample>& planes) {
  const int chromaWidth = encodedWidth / layout.chromaColumns;
  const int chromaHeight = encodedHeight / layout.chromaRows;
  const size_t lumaSize = static_cast<size_t>(encodedWidth) * encodedHeight;
  const size_t chromaSize = static_cast<size_t>(chromaWidth) * chromaHeight;
  planes.resize(lumaSize * (layout.alpha ? 2 : 1) + 2 * chromaSize);
  const Weights k{matrix.kr, 1.0f - matrix.kr - matrix.kb, matrix.kb};
  const float scale = static_cast<float>(1 << (layout.bits - 8));
  // Codes from the colour differences B' - E'y and R' - E'y (ITU-R BT.709 section 3), of the
  // mean of the pixels a chroma sample covers.
  const float blueScale = 224.0f / (2.0f * (1.0f - k.kb)),
              redScale = 224.0f / (2.0f * (1.0f - k.kr));
  const float meanOfSums = 1.0f / static_cast<float>(layout.chromaColumns * layout.chromaRows);
  Sample* luma = planes.data();
  Sample* cb = luma + lumaSize;
  Sample* cr = cb + chromaSize;
  Sample* alpha = layout.alpha ? cr + chromaSize : nullptr;
  const float alphaScale = static_cast<float>((1 << layout.bits) - 1);
  const LegalCodes legal = legalCodes(layout.bits);
  forEachBlock(size_t(chromaHeight), 1, [&](size_t firstRow, size_t endRow) {
    std::vector<float> sums(static_cast<size_t>(chromaWidth) * 3);  // R', G', B' planes
    std::vector<float> row(static_cast<size_t>(image.width) * 4);   // legal
    const float* r = sums.data();
    const float* g = r + chromaWidth;
    const float* b = g + chromaWidth;
    for (int cy = int(firstRow); cy < int(endRow); ++cy) {
      std::fill(sums.begin(), sums.end(), 0.0f);
      for (int y = cy * layout.chromaRows; y < (cy + 1) * layout.chromaRows; ++y) {
        legalRow(image.pixel(0, std::min(y, image.height - 1)), image.width, legal, row.data());
        Sample* lumaOut = luma + static_cast<size_t>(y) * encodedWidth;
        lumaRow(row.data(), image.width, k, scale, lumaOut);
        if (encodedWidth > image.width) lumaOut[image.width] = lumaOut[image.width - 1];
        if (alpha) {
          Sample* alphaOut = alpha + static_cast<size_t>(y) * encodedWidth;
          for (int x = 0; x < image.width; ++x)
            alphaOut[x] = rounded<Sample>(row[static_cast<size_t>(x) * 4 + 3] * alphaScale);
          if (encodedWidth > image.width) alphaOut[image.width] = alphaOut[image.width - 1];
        }
        addChromaSums(row.data(), image.width, layout.chromaColumns, chromaWidth, sums.data());
      }
      Sample* cbRow = cb + static_cast<size_t>(cy) * chromaWidth;
      Sample* crRow = cr + static_cast<size_t>(cy) * chromaWidth;
      for (int cx = 0; cx < chromaWidth; ++cx) {
        const float ey = (k.kr * r[cx] + k.kg * g[cx] + k.kb * b[cx]) * meanOfSums;
        cbRow[cx] =
            legalRounded<Sample>((128.0f + blueScale * (b[cx] * meanOfSums - ey)) * scale, legal);
        crRow[cx] =
            legalRounded<Sample>((128.0f + redScale * (r[cx] * meanOfSums - ey)) * scale, legal);
      }
    }
  });
}

template void packYcbcr<uint8_t>(const Image&, int, int, const YcbcrLayout&, const YcbcrMatrix&,
                                 std::vector<uint8_t>&);
template void packYcbcr<uint16_t>(const Image&, int, int, const YcbcrLayout&, const YcbcrMatrix&,
                                  std::vector<uint16_t>&);

}  // namespace pluvia
