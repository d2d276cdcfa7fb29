#include "optics/paper_transfer_table.h"

#include <algorithm>
#include <cmath>

namespace pluvia::optics {
namespace {

// Face f: 0 +X, 1 -X, 2 +Y, 3 -Y, 4 +Z, 5 -Z; (s, t) in [-1, 1] on the face.
std::array<double, 3> faceDirection(int face, double s, double t) {
  std::array<double, 3> d;
  switch (face) {
    case 0:
      d = {1.0, t, -s};
      break;
    case 1:
      d = {-1.0, t, s};
      break;
    case 2:
      d = {s, 1.0, -t};
      break;
    case 3:
      d = {s, -1.0, t};
      break;
    case 4:
      d = {s, t, 1.0};
      break;
    default:
      d = {-s, t, -1.0};
      break;
  }
  const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  return {d[0] / length, d[1] / length, d[2] / length};
}

}  // namespace

PaperTransferTable::PaperTransferTable(const std::array<std::vector<double>, 3>& zonal,
                                       int faceSize)
    : faceSize_(faceSize), coefficients_(int(zonal[0].size() * zonal[0].size())) {
  transfers_.resize(size_t(directions()) * 3 * size_t(coefficients_));
  for (int face = 0; face < 6; ++face) {
    for (int j = 0; j < faceSize; ++j) {
      for (int i = 0; i < faceSize; ++i) {
        const double s = 2.0 * (i + 0.5) / faceSize - 1.0, t = 2.0 * (j + 0.5) / faceSize - 1.0;
        const std::array<double, 3> view = faceDirection(face, s, t);
        const size_t texel =
            (size_t(face) * size_t(faceSize) + size_t(j)) * size_t(faceSize) + size_t(i);
        for (size_t c = 0; c < 3; ++c) {
          const std::vector<double> transfer = rotatedTransfer(zonal[c], view);
          float* out = transfers_.data() + (texel * 3 + c) * size_t(coefficients_);
          for (int k = 0; k < coefficients_; ++k) out[k] = float(transfer[size_t(k)]);
        }
      }
    }
  }
}

size_t PaperTransferTable::texelIndex(const std::array<double, 3>& v) const {
  const double ax = std::abs(v[0]), ay = std::abs(v[1]), az = std::abs(v[2]);
  int face;
  double s, t;  // inverse of faceDirection
  if (ax >= ay && ax >= az) {
    face = v[0] > 0 ? 0 : 1;
    s = v[0] > 0 ? -v[2] / ax : v[2] / ax;
    t = v[1] / ax;
  } else if (ay >= az) {
    face = v[1] > 0 ? 2 : 3;
    s = v[0] / ay;
    t = v[1] > 0 ? -v[2] / ay : v[2] / ay;
  } else {
    face = v[2] > 0 ? 4 : 5;
    s = v[2] > 0 ? v[0] / az : -v[0] / az;
    t = v[1] / az;
  }
  const int i = std::clamp(int((s + 1.0) * 0.5 * faceSize_), 0, faceSize_ - 1);
  const int j = std::clamp(int((t + 1.0) * 0.5 * faceSize_), 0, faceSize_ - 1);
  return (size_t(face) * size_t(faceSize_) + size_t(j)) * size_t(faceSize_) + size_t(i);
}

std::array<double, 3> PaperTransferTable::shade(const ShCoefficients& environment,
                                                const std::array<double, 3>& view) const {
  const size_t texel = texelIndex(view);
  std::array<double, 3> radiance{0.0, 0.0, 0.0};
  const size_t count = std::min(size_t(coefficients_), environment.size());
  for (size_t c = 0; c < 3; ++c) {
    const float* transfer = transfers_.data() + (texel * 3 + c) * size_t(coefficients_);
    for (size_t k = 0; k < count; ++k) radiance[c] += transfer[k] * environment[k][c];
  }
  return radiance;
}

}  // namespace pluvia::optics
