#include "optics/sh.h"

#include <cmath>
#include <stdexcept>

namespace pluvia::optics {
namespace {

// K_lm = sqrt((2l + 1) / (4 pi) * (l - m)! / (l + m)!)
double normalisation(int l, int m) {
  double ratio = 1.0;
  for (int k = l - m + 1; k <= l + m; ++k) ratio /= double(k);
  return std::sqrt((2.0 * l + 1.0) / (4.0 * M_PI) * ratio);
}

}  // namespace

void shBasis(int order, const std::array<double, 3>& d, std::vector<double>& basis) {
  if (order < 0) throw std::invalid_argument("SH order must be >= 0");
  basis.assign(size_t((order + 1) * (order + 1)), 0.0);
  const double x = d[0], y = d[1], z = d[2];
  // cos(m phi) sin^m(theta) + i sin(m phi) sin^m(theta) = (x + i y)^m.
  double cosPart = 1.0, sinPart = 0.0;
  for (int m = 0; m <= order; ++m) {
    // P_l^m(z) / sin^m(theta), without the Condon-Shortley phase, for l = m, m+1, ...
    double doubleFactorial = 1.0;
    for (int k = 2 * m - 1; k > 1; k -= 2) doubleFactorial *= k;
    double previous = 0.0, current = doubleFactorial;
    for (int l = m; l <= order; ++l) {
      if (l == m + 1) {
        previous = current;
        current = z * (2.0 * m + 1.0) * previous;
      } else if (l > m + 1) {
        const double next =
            ((2.0 * l - 1.0) * z * current - (l + m - 1.0) * previous) / double(l - m);
        previous = current;
        current = next;
      }
      const double k = normalisation(l, m) * current;
      if (m == 0) {
        basis[size_t(l * l + l)] = k;
      } else {
        basis[size_t(l * l + l + m)] = std::sqrt(2.0) * k * cosPart;
        basis[size_t(l * l + l - m)] = std::sqrt(2.0) * k * sinPart;
      }
    }
    const double nextCos = cosPart * x - sinPart * y;
    sinPart = cosPart * y + sinPart * x;
    cosPart = nextCos;
  }
}

double shWindowFactor(ShWindow window, int l, int order) {
  const double t = double(l) / double(order + 1);
  switch (window) {
    case ShWindow::None:
      return 1.0;
    case ShWindow::Hann:
      return 0.5 * (1.0 + std::cos(M_PI * t));
    case ShWindow::Lanczos:
      return l == 0 ? 1.0 : std::sin(M_PI * t) / (M_PI * t);
  }
  return 1.0;
}

ShCoefficients projectEnvironment(const EquirectMap& environment, int order, ShWindow window) {
  if (environment.empty()) throw std::invalid_argument("empty environment map");
  const size_t count = size_t((order + 1) * (order + 1));
  std::vector<std::array<double, 3>> sums(count, {0.0, 0.0, 0.0});
  std::vector<double> basis;
  for (int y = 0; y < environment.height; ++y) {
    const double solidAngle = equirectTexelSolidAngle(environment.width, environment.height, y);
    for (int x = 0; x < environment.width; ++x) {
      shBasis(order, equirectTexelDirection(environment.width, environment.height, x, y), basis);
      const float* radiance = environment.texel(x, y);
      for (size_t i = 0; i < count; ++i) {
        for (int c = 0; c < 3; ++c) sums[i][c] += radiance[c] * basis[i] * solidAngle;
      }
    }
  }
  for (int l = 0; l <= order; ++l) {
    const double factor = shWindowFactor(window, l, order);
    for (int m = -l; m <= l; ++m) {
      for (int c = 0; c < 3; ++c) sums[size_t(l * l + l + m)][c] *= factor;
    }
  }
  return sums;
}

double zonalRotationFactor(int l) {
  return std::sqrt(4.0 * M_PI / (2.0 * l + 1.0));
}

std::vector<double> rotatedTransfer(const std::vector<double>& zonal,
                                    const std::array<double, 3>& view) {
  const int order = int(zonal.size()) - 1;
  std::vector<double> basis;
  shBasis(order, view, basis);
  for (int l = 0; l <= order; ++l) {
    const double scale = zonalRotationFactor(l) * zonal[size_t(l)];
    for (int m = -l; m <= l; ++m) basis[size_t(l * l + l + m)] *= scale;
  }
  return basis;
}

std::array<double, 3> shadeZonal(const ShCoefficients& environment,
                                 const std::array<std::vector<double>, 3>& zonal,
                                 const std::array<double, 3>& view) {
  int order = int(zonal[0].size()) - 1;
  while ((order + 1) * (order + 1) > int(environment.size())) --order;
  thread_local std::vector<double> basis;  // no allocation per drop
  shBasis(order, view, basis);
  std::array<double, 3> radiance{0.0, 0.0, 0.0};
  for (int l = 0; l <= order; ++l) {
    const double rotation = zonalRotationFactor(l);
    for (int m = -l; m <= l; ++m) {
      const size_t i = size_t(l * l + l + m);
      for (size_t c = 0; c < 3; ++c)
        radiance[c] += rotation * zonal[c][size_t(l)] * basis[i] * environment[i][c];
    }
  }
  return radiance;
}

}  // namespace pluvia::optics
