#include "image/ops.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>
#include <opencv2/imgproc.hpp>

#include "util/parallel.h"

namespace pluvia::ops {
namespace {

// Rows per task: a frame of 1080 rows gives both cores dozens of tasks.
constexpr size_t kRowsPerTask = 16;

// Calls f(firstPixel, pixelCount) over bands of whole rows, in parallel.
template <typename F>
void forRowBands(const Image& image, F&& f) {
  const size_t width = static_cast<size_t>(image.width);
  forEachBlock(
      static_cast<size_t>(image.height), kRowsPerTask,
      [&](size_t firstRow, size_t endRow) { f(firstRow * width, (endRow - firstRow) * width); });
}

// OpenCV's BORDER_REFLECT (fedcba|abcdefgh|hgfedcb), reflected again for a kernel wider than
// the image.
int reflect(int i, int size) {
  while (i < 0 || i >= size) i = i < 0 ? -i - 1 : 2 * size - i - 1;
  return i;
}

// Kernel radii with their own unrolled loops (the presets' sigmas of 0.4-0.8 px give 2-4);
// others take the general loop. kAnyRadius marks the general case.
constexpr int kAnyRadius = 0;

// out = row convolved with the kernel along x, all four channels (alpha's result is unused).
template <int kRadius>
__attribute__((target_clones("arch=x86-64-v3", "default"))) void blurRow(
    const float* row, int width, const float* weights, int runtimeRadius, float* out) {
  const int radius = kRadius == kAnyRadius ? runtimeRadius : kRadius;
  auto tap = [&](int x) {
    float sum[4] = {0, 0, 0, 0};
    for (int k = -radius; k <= radius; ++k) {
      const float* p = row + static_cast<size_t>(reflect(x + k, width)) * 4;
      for (int c = 0; c < 4; ++c) sum[c] += weights[k + radius] * p[c];
    }
    std::copy_n(sum, 4, out + static_cast<size_t>(x) * 4);
  };
  const int interiorFirst = std::min(radius, width), interiorEnd = std::max(width - radius, 0);
  for (int x = 0; x < interiorFirst; ++x) tap(x);
  // The interior needs no reflection: plain loops over floats the compiler vectorises.
  for (size_t i = static_cast<size_t>(interiorFirst) * 4; i < static_cast<size_t>(interiorEnd) * 4;
       ++i) {
    float sum = 0.0f;
    for (int k = -radius; k <= radius; ++k) sum += weights[k + radius] * row[i + k * 4];
    out[i] = sum;
  }
  for (int x = std::max(interiorEnd, interiorFirst); x < width; ++x) tap(x);
}

// The image row out gets sum_k weights[k] * rows[k] in R, G, B; its alpha is kept.
template <int kRadius>
__attribute__((target_clones("arch=x86-64-v3", "default"))) void sumRowsInto(
    const float* const* rows, const float* weights, int runtimeRadius, size_t floats, float* out) {
  const int radius = kRadius == kAnyRadius ? runtimeRadius : kRadius;
  if constexpr (kRadius != kAnyRadius) {
    // Rows and weights in locals, so the compiler keeps them in registers and vectorises.
    const float* __restrict in[2 * kRadius + 1];
    float w[2 * kRadius + 1];
    for (int k = 0; k <= 2 * kRadius; ++k) in[k] = rows[k], w[k] = weights[k];
    for (size_t i = 0; i < floats; i += 4) {
      for (size_t c = 0; c < 3; ++c) {
        float sum = 0.0f;
        for (int k = 0; k <= 2 * kRadius; ++k) sum += w[k] * in[k][i + c];
        out[i + c] = sum;
      }
    }
    return;
  }
  for (size_t i = 0; i < floats; ++i) {
    float sum = 0.0f;
    for (int k = 0; k <= 2 * radius; ++k) sum += weights[k] * rows[k][i];
    out[i] = (i & 3) == 3 ? out[i] : sum;
  }
}

// The two passes of a kernel radius.
struct BlurPasses {
  void (*row)(const float*, int, const float*, int, float*);
  void (*column)(const float* const*, const float*, int, size_t, float*);
};

BlurPasses blurPasses(int radius) {
  switch (radius) {
    case 1:
      return {blurRow<1>, sumRowsInto<1>};
    case 2:
      return {blurRow<2>, sumRowsInto<2>};
    case 3:
      return {blurRow<3>, sumRowsInto<3>};
    case 4:
      return {blurRow<4>, sumRowsInto<4>};
    default:
      return {blurRow<kAnyRadius>, sumRowsInto<kAnyRadius>};
  }
}

}  // namespace

void darken(Image& image, float amount, float darkening, const float* weight) {
  if (amount == 0.0f) return;
  forRowBands(image, [&](size_t first, size_t count) {
    for (size_t i = first; i < first + count; ++i) {
      const float a = weight ? amount * weight[i] : amount;
      const float scale = 1.0f - a * darkening;
      float* p = image.rgba.data() + i * 4;
      const float y = luminance(p);
      for (int c = 0; c < 3; ++c) p[c] = ((1.0f - a) * p[c] + a * y) * scale;
    }
  });
}

// Separable, in place, in bands of rows drawn in parallel. A band keeps the rows blurred along
// x that its output rows need in a ring; the rows above and below it (its halo: another band's
// rows, or reflections at the image's top and bottom, which this band may already have
// overwritten) are blurred along x before any band writes.
void gaussianBlur(Image& image, float sigmaPx) {
  gaussianBlurToward(image, sigmaPx, nullptr);
}

// `weight` null: the blur itself, written in place. Else each output row is blurred into a
// scratch row and mixed into the image row, which no later row reads (rows below are read before
// they are overwritten, rows above come from the ring or the halo).
void gaussianBlurToward(Image& image, float sigmaPx, const float* weight) {
  if (sigmaPx <= 0.0f || image.empty()) return;
  // Kernel of +-4 sigma, OpenCV's own weights (what cv::GaussianBlur used here before).
  const int radius = std::max(1, static_cast<int>(std::ceil(4.0f * sigmaPx)));
  const cv::Mat kernel = cv::getGaussianKernel(2 * radius + 1, sigmaPx, CV_32F);
  const float* weights = kernel.ptr<float>();
  const BlurPasses passes = blurPasses(radius);
  const int width = image.width, height = image.height;
  const size_t rowFloats = static_cast<size_t>(width) * 4;
  auto inputRow = [&](int y) { return image.rgba.data() + static_cast<size_t>(y) * rowFloats; };

  const int bandRows = std::max(static_cast<int>(kRowsPerTask) * 2, 2 * radius);
  const int bands = (height + bandRows - 1) / bandRows;
  // Halo rows of band b: virtual rows y0 - radius .. y0 - 1, then y1 .. y1 + radius - 1.
  std::vector<float> halos(static_cast<size_t>(bands) * 2 * radius * rowFloats);
  auto halo = [&](int band, int k) {
    return halos.data() + (static_cast<size_t>(band) * 2 * radius + k) * rowFloats;
  };
  forEachIndex(bands, [&](int band) {
    const int y0 = band * bandRows, y1 = std::min(y0 + bandRows, height);
    for (int k = 0; k < radius; ++k) {
      passes.row(inputRow(reflect(y0 - radius + k, height)), width, weights, radius, halo(band, k));
      passes.row(inputRow(reflect(y1 + k, height)), width, weights, radius, halo(band, radius + k));
    }
  });

  forEachIndex(bands, [&](int band) {
    const int y0 = band * bandRows, y1 = std::min(y0 + bandRows, height);
    const int taps = 2 * radius + 1;
    std::vector<float> ring(static_cast<size_t>(taps) * rowFloats);
    std::vector<float> blurred(weight ? rowFloats : 0);
    std::vector<const float*> window(static_cast<size_t>(taps));
    // Virtual row j, blurred along x: from the halo outside the band, else blurred now into
    // the ring (rows of the band below the output row are not yet overwritten).
    auto rowAt = [&](int j) -> const float* {
      if (j < y0) return halo(band, j - (y0 - radius));
      if (j >= y1) return halo(band, radius + (j - y1));
      float* slot = ring.data() + static_cast<size_t>(j % taps) * rowFloats;
      passes.row(inputRow(j), width, weights, radius, slot);
      return slot;
    };
    for (int j = y0 - radius; j < y0 + radius; ++j)
      window[static_cast<size_t>(j - y0 + radius)] = rowAt(j);
    for (int y = y0; y < y1; ++y) {
      window[static_cast<size_t>(taps - 1)] = rowAt(y + radius);
      float* out = inputRow(y);
      passes.column(window.data(), weights, radius, rowFloats, weight ? blurred.data() : out);
      if (weight) {
        const float* w = weight + static_cast<size_t>(y) * width;
        for (int x = 0; x < width; ++x) {
          float* p = out + static_cast<size_t>(x) * 4;
          const float* t = blurred.data() + static_cast<size_t>(x) * 4;
          for (int c = 0; c < 3; ++c) p[c] += w[x] * (t[c] - p[c]);
        }
      }
      std::rotate(window.begin(), window.begin() + 1, window.end());
    }
  });
}

void fog(Image& image, float densityPerMeter, const std::array<float, 3>& fogRgb,
         float maxDepthMeters) {
  if (densityPerMeter == 0.0f) return;
  const std::vector<float>& depth = image.plane(kDepthPlane);
  forRowBands(image, [&](size_t first, size_t count) {
    // Depth planes repeat values (a backdrop, the ground along a row): exp() only when the
    // depth changes.
    float lastDepth = std::numeric_limits<float>::quiet_NaN(), alpha = 0.0f;
    for (size_t i = first; i < first + count; ++i) {
      if (!(depth[i] < std::numeric_limits<float>::infinity())) continue;  // sky: its own airlight
      if (depth[i] != lastDepth) {
        lastDepth = depth[i];
        alpha = 1.0f - std::exp(-densityPerMeter * std::min(depth[i], maxDepthMeters));
      }
      float* p = image.rgba.data() + i * 4;
      for (int c = 0; c < 3; ++c) p[c] = alpha * fogRgb[c] + (1.0f - alpha) * p[c];
    }
  });
}

size_t replaceNonFinite(Image& image) {
  return tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, image.pixelCount(), kRowsPerTask * 1024), size_t{0},
      [&](const auto& pixels, size_t replaced) {
        for (size_t i = pixels.begin(); i != pixels.end(); ++i) {
          float* p = image.rgba.data() + i * 4;
          for (int c = 0; c < 4; ++c) {
            if (!std::isfinite(p[c])) {
              p[c] = c == 3 ? 1.0f : 0.0f;
              ++replaced;
            }
          }
        }
        return replaced;
      },
      std::plus<>());
}

}  // namespace pluvia::ops
