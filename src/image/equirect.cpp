#include "image/equirect.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace pluvia {

EquirectMap::EquirectMap(int w, int h)
    : width(w), height(h), rgb(size_t(w) * size_t(h) * 3, 0.0f) {}

std::array<double, 2> equirectUv(const std::array<double, 3>& d) {
  double u = 0.5 + std::atan2(d[0], -d[2]) / (2.0 * M_PI);
  if (u >= 1.0) u -= 1.0;
  const double v = std::acos(std::clamp(d[1], -1.0, 1.0)) / M_PI;
  return {u, v};
}

std::array<double, 3> equirectDirection(double u, double v) {
  const double phi = (u - 0.5) * 2.0 * M_PI;  // atan2(x, -z)
  const double theta = v * M_PI;              // from +Y
  const double s = std::sin(theta);
  return {s * std::sin(phi), std::cos(theta), -s * std::cos(phi)};
}

std::array<double, 3> equirectTexelDirection(int width, int height, int x, int y) {
  return equirectDirection((x + 0.5) / width, (y + 0.5) / height);
}

double equirectTexelSolidAngle(int width, int height, int y) {
  const double theta0 = M_PI * y / height;
  const double theta1 = M_PI * (y + 1) / height;
  return 2.0 * M_PI / width * (std::cos(theta0) - std::cos(theta1));
}

std::array<float, 3> equirectBandMean(const EquirectMap& map, double minElevationDeg,
                                      double maxElevationDeg) {
  // Elevation e is polar angle theta = 90 deg - e; the band is theta in [thetaLo, thetaHi].
  const double thetaLo = (90.0 - maxElevationDeg) * M_PI / 180.0;
  const double thetaHi = (90.0 - minElevationDeg) * M_PI / 180.0;
  std::array<double, 3> sum{0, 0, 0};
  double total = 0.0;
  for (int y = 0; y < map.height; ++y) {
    const double theta0 = std::max(thetaLo, M_PI * y / map.height);
    const double theta1 = std::min(thetaHi, M_PI * (y + 1) / map.height);
    if (theta1 <= theta0) continue;
    const double w = std::cos(theta0) - std::cos(theta1);
    for (int x = 0; x < map.width; ++x)
      for (int c = 0; c < 3; ++c) sum[size_t(c)] += w * map.texel(x, y)[c];
    total += w * map.width;
  }
  if (!(total > 0.0)) return {0, 0, 0};
  return {float(sum[0] / total), float(sum[1] / total), float(sum[2] / total)};
}

std::array<float, 3> sampleEquirect(const EquirectMap& map, float x, float y, float z) {
  constexpr float kTwoPi = 6.28318530717958648f;
  constexpr float kPi = 3.14159265358979324f;
  const float u = 0.5f + std::atan2(x, -z) / kTwoPi;
  const float v = std::acos(std::clamp(y, -1.0f, 1.0f)) / kPi;
  // Texel coordinates with centres on integers.
  const float px = u * float(map.width) - 0.5f;
  const float py = std::clamp(v * float(map.height) - 0.5f, 0.0f, float(map.height - 1));
  const float x0f = std::floor(px);
  const float y0f = std::floor(py);
  const float fx = px - x0f;
  const float fy = py - y0f;
  const int x0 = (int(x0f) % map.width + map.width) % map.width;
  const int x1 = (x0 + 1) % map.width;
  const int y0 = int(y0f);
  const int y1 = std::min(y0 + 1, map.height - 1);
  std::array<float, 3> out;
  for (int c = 0; c < 3; ++c) {
    const float a = map.texel(x0, y0)[c], b = map.texel(x1, y0)[c];
    const float d = map.texel(x0, y1)[c], e = map.texel(x1, y1)[c];
    const float top = a + fx * (b - a);
    const float bottom = d + fx * (e - d);
    out[c] = top + fy * (bottom - top);
  }
  return out;
}

EquirectMap uniformEquirect(int width, int height, const std::array<float, 3>& radiance) {
  EquirectMap map(width, height);
  for (size_t i = 0; i < map.rgb.size(); ++i) map.rgb[i] = radiance[i % 3];
  return map;
}

namespace {

// Overlap weights of output cell o (covering [o, o+1) * inputCount / outputCount in input cells)
// with input cells: (input index, overlap length in input cells).
std::vector<std::pair<int, double>> overlaps(int o, int inputCount, int outputCount) {
  const double scale = double(inputCount) / double(outputCount);
  const double begin = o * scale, end = (o + 1) * scale;
  std::vector<std::pair<int, double>> out;
  for (int i = int(std::floor(begin)); i < int(std::ceil(end)) && i < inputCount; ++i) {
    const double overlap = std::min(end, i + 1.0) - std::max(begin, double(i));
    if (overlap > 0.0) out.emplace_back(i, overlap);
  }
  return out;
}

}  // namespace

EquirectMap resampleEquirect(const EquirectMap& map, int width, int height) {
  if (map.empty() || width < 1 || height < 1) {
    throw std::invalid_argument("resampleEquirect: empty map or size");
  }
  // Along u every texel of a row has the same solid angle: a plain box filter.
  EquirectMap rows(width, map.height);
  for (int x = 0; x < width; ++x) {
    const auto weights = overlaps(x, map.width, width);
    for (int y = 0; y < map.height; ++y) {
      double sum[3] = {0, 0, 0}, total = 0.0;
      for (const auto& [ix, w] : weights) {
        for (int c = 0; c < 3; ++c) sum[c] += w * map.texel(ix, y)[c];
        total += w;
      }
      for (int c = 0; c < 3; ++c) rows.texel(x, y)[c] = float(sum[c] / total);
    }
  }
  // Along v each input row is weighted by its solid angle (times the fraction overlapped).
  EquirectMap out(width, height);
  for (int y = 0; y < height; ++y) {
    const auto weights = overlaps(y, map.height, height);
    for (int x = 0; x < width; ++x) {
      double sum[3] = {0, 0, 0}, total = 0.0;
      for (const auto& [iy, fraction] : weights) {
        const double w = fraction * equirectTexelSolidAngle(map.width, map.height, iy);
        for (int c = 0; c < 3; ++c) sum[c] += w * rows.texel(x, iy)[c];
        total += w;
      }
      for (int c = 0; c < 3; ++c) out.texel(x, y)[c] = float(sum[c] / total);
    }
  }
  return out;
}

}  // namespace pluvia
