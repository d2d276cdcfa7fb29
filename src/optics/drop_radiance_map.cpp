#include "optics/drop_radiance_map.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <opencv2/core.hpp>

#include "util/parallel.h"

namespace pluvia::optics {
namespace {

bool sameOptics(const DropOptics& a, const DropOptics& b) {
  return a.eta == b.eta && a.terms == b.terms;
}

// The kernel of output row `outRow` against input row `inRow`, for every column offset s: D of
// the angle between output texel i and input texel q = ratio * i + s (ratio = inWidth /
// outWidth), averaged over sub-samples of the input texel's footprint, times its solid angle.
// It depends on s only, not on i. Output texel i is centred at input column ratio * i +
// ratio / 2, so sub-sample b of input column q lies s - ratio / 2 + (b + 0.5) / subsamples
// columns from it.
void rowKernel(const TransferTable& table, int outRow, int outHeight, int inRow, int inWidth,
               int inHeight, int subsamples, const std::vector<double>& cosDeltaPhi,
               std::vector<double>& kernel) {
  const double thetaOut = M_PI * (outRow + 0.5) / outHeight;
  const double sinOut = std::sin(thetaOut), cosOut = std::cos(thetaOut);
  kernel.assign(size_t(inWidth), 0.0);
  double weight = 0.0;
  for (int a = 0; a < subsamples; ++a) {
    const double theta = M_PI * (inRow + (a + 0.5) / subsamples) / inHeight;
    const double sinIn = std::sin(theta), cosIn = std::cos(theta);
    // sin(theta) weights the sub-rows by their share of the solid angle.
    weight += sinIn * subsamples;
    const double scale = sinOut * sinIn, offset = cosOut * cosIn;
    for (int s = 0; s < inWidth; ++s) {
      const double* cosines = cosDeltaPhi.data() + size_t(s) * size_t(subsamples);
      double sum = 0.0;
      for (int b = 0; b < subsamples; ++b) sum += table.at(scale * cosines[b] + offset);
      kernel[size_t(s)] += sinIn * sum;
    }
  }
  const double solidAngle = equirectTexelSolidAngle(inWidth, inHeight, inRow);
  for (double& k : kernel) k *= solidAngle / weight;
}

// cos of the longitude difference of sub-sample b of column offset s (see rowKernel).
std::vector<double> subsampleCosDeltaPhi(int inWidth, int ratio, int subsamples) {
  std::vector<double> cosines(size_t(inWidth) * size_t(subsamples));
  for (int s = 0; s < inWidth; ++s) {
    for (int b = 0; b < subsamples; ++b) {
      const double columns = s - 0.5 * ratio + (b + 0.5) / subsamples;
      cosines[size_t(s) * size_t(subsamples) + size_t(b)] =
          std::cos(2.0 * M_PI * columns / inWidth);
    }
  }
  return cosines;
}

}  // namespace

EquirectMap buildDropRadianceMap(const EquirectMap& environment,
                                 const std::array<DropOptics, 3>& optics,
                                 const RadianceMapSettings& settings) {
  if (environment.empty()) throw std::invalid_argument("empty environment map");
  if (settings.outputWidth < 4 || settings.outputWidth % 2 != 0 ||
      settings.inputWidth % settings.outputWidth != 0) {
    throw std::invalid_argument("radiance map: outputWidth must be even and divide inputWidth");
  }
  const int outWidth = settings.outputWidth, outHeight = outWidth / 2;
  const int inWidth = settings.inputWidth, inHeight = inWidth / 2;
  const int ratio = inWidth / outWidth;
  const EquirectMap input = resampleEquirect(environment, inWidth, inHeight);

  std::array<TransferTable, 3> tables;
  for (int c = 0; c < 3; ++c) {
    tables[size_t(c)] = (c > 0 && sameOptics(optics[size_t(c)], optics[0]))
                            ? tables[0]
                            : binTransfer(optics[size_t(c)], settings.bins);
  }
  const bool oneTable = sameOptics(optics[1], optics[0]) && sameOptics(optics[2], optics[0]);

  // The sum over input columns is a circular correlation along u for every pair of rows: done
  // in the Fourier domain, where the sum over input rows can be taken before the one inverse
  // transform per output row. Double precision: a sun may outshine a texel by 1e6.
  std::vector<cv::Mat> rowSpectra(size_t(inHeight) * 3);
  for (int y = 0; y < inHeight; ++y) {
    for (int c = 0; c < 3; ++c) {
      cv::Mat row(1, inWidth, CV_64F);
      for (int x = 0; x < inWidth; ++x) row.at<double>(0, x) = input.texel(x, y)[c];
      cv::dft(row, rowSpectra[size_t(y) * 3 + size_t(c)], cv::DFT_COMPLEX_OUTPUT);
    }
  }

  const std::vector<double> cosDeltaPhi =
      subsampleCosDeltaPhi(inWidth, ratio, settings.kernelSubsamples);
  // The kernel of output row o against input row i is that of the rows mirrored about the
  // equator (outHeight - 1 - o against inHeight - 1 - i): both polar angles become pi minus
  // themselves, so their sines stay and the product of their cosines too. Each kernel is made
  // once, for a row of the upper half, and serves its mirror row with the mirrored input row.
  EquirectMap out(outWidth, outHeight);
  forEachRow((outHeight + 1) / 2, [&](int outRow) {
    const int mirrorRow = outHeight - 1 - outRow;
    std::array<cv::Mat, 3> accumulated, mirrored;
    for (auto& a : accumulated) a = cv::Mat::zeros(1, inWidth, CV_64FC2);
    for (auto& a : mirrored) a = cv::Mat::zeros(1, inWidth, CV_64FC2);
    std::vector<double> kernel;
    cv::Mat kernelSpectrum, product;
    for (int inRow = 0; inRow < inHeight; ++inRow) {
      const int mirrorInRow = inHeight - 1 - inRow;
      for (int c = 0; c < 3; ++c) {
        if (c == 0 || !oneTable) {
          rowKernel(tables[size_t(c)], outRow, outHeight, inRow, inWidth, inHeight,
                    settings.kernelSubsamples, cosDeltaPhi, kernel);
          cv::dft(cv::Mat(1, inWidth, CV_64F, kernel.data()), kernelSpectrum,
                  cv::DFT_COMPLEX_OUTPUT);
        }
        // sum_s K[s] L[q + s] <-> conj(K^) L^
        cv::mulSpectrums(rowSpectra[size_t(inRow) * 3 + size_t(c)], kernelSpectrum, product, 0,
                         true);
        accumulated[size_t(c)] += product;
        if (mirrorRow == outRow) continue;
        cv::mulSpectrums(rowSpectra[size_t(mirrorInRow) * 3 + size_t(c)], kernelSpectrum, product,
                         0, true);
        mirrored[size_t(c)] += product;
      }
    }
    auto writeRow = [&](int row, const std::array<cv::Mat, 3>& sums) {
      for (int c = 0; c < 3; ++c) {
        cv::Mat correlation;
        cv::idft(sums[size_t(c)], correlation, cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
        for (int i = 0; i < outWidth; ++i)
          out.texel(i, row)[c] = float(correlation.at<double>(0, i * ratio));
      }
    };
    writeRow(outRow, accumulated);
    if (mirrorRow != outRow) writeRow(mirrorRow, mirrored);
  });
  return out;
}

}  // namespace pluvia::optics
