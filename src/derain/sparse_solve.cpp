#include "derain/sparse_solve.h"

#include <cmath>

namespace pluvia::derain {
namespace {

// Which forward differences exist: a zero component needs no neighbour in its direction.
struct DirectionalTerms {
  bool useX, useY;
  int lastX, lastY;  // terms exist for x < lastX, y < lastY
};

DirectionalTerms directionalTerms(const GridSize& grid, double dx, double dy) {
  const bool useX = dx != 0.0, useY = dy != 0.0;
  return {useX, useY, useX ? grid.width - 1 : grid.width, useY ? grid.height - 1 : grid.height};
}

double dot(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) sum += double(a[i]) * double(b[i]);
  return sum;
}

}  // namespace

void addDirectionalGram(const GridSize& grid, double dx, double dy, double weight, const float* x,
                        float* y) {
  const DirectionalTerms t = directionalTerms(grid, dx, dy);
  const float wx = float(weight * dx), wy = float(weight * dy);
  const float fx = float(dx), fy = float(dy);
  const size_t w = size_t(grid.width);
  for (int row = 0; row < t.lastY; ++row) {
    const size_t base = size_t(row) * w;
    for (int col = 0; col < t.lastX; ++col) {
      const size_t p = base + size_t(col);
      const float ax = t.useX ? x[p + 1] - x[p] : 0.0f;
      const float ay = t.useY ? x[p + w] - x[p] : 0.0f;
      const float g = fx * ax + fy * ay;
      y[p] -= (wx + wy) * g;
      if (t.useX) y[p + 1] += wx * g;
      if (t.useY) y[p + w] += wy * g;
    }
  }
}

void addDirectionalGramDiagonal(const GridSize& grid, double dx, double dy, double weight,
                                float* diagonal) {
  const DirectionalTerms t = directionalTerms(grid, dx, dy);
  const size_t w = size_t(grid.width);
  for (int row = 0; row < t.lastY; ++row)
    for (int col = 0; col < t.lastX; ++col) {
      const size_t p = size_t(row) * w + size_t(col);
      diagonal[p] += float(weight * (dx + dy) * (dx + dy));
      if (t.useX) diagonal[p + 1] += float(weight * dx * dx);
      if (t.useY) diagonal[p + w] += float(weight * dy * dy);
    }
}

double directionalEnergy(const GridSize& grid, double dx, double dy, const float* x) {
  const DirectionalTerms t = directionalTerms(grid, dx, dy);
  const size_t w = size_t(grid.width);
  double sum = 0.0;
  for (int row = 0; row < t.lastY; ++row)
    for (int col = 0; col < t.lastX; ++col) {
      const size_t p = size_t(row) * w + size_t(col);
      const double g =
          (t.useX ? dx * (x[p + 1] - x[p]) : 0.0) + (t.useY ? dy * (x[p + w] - x[p]) : 0.0);
      sum += g * g;
    }
  return sum;
}

void addLaplacian(const GridSize& grid, double weight, const float* x, float* y) {
  const float wf = float(weight);
  const size_t w = size_t(grid.width);
  for (int row = 0; row < grid.height; ++row)
    for (int col = 0; col < grid.width; ++col) {
      const size_t p = size_t(row) * w + size_t(col);
      if (col + 1 < grid.width) {
        const float g = wf * (x[p + 1] - x[p]);
        y[p] -= g;
        y[p + 1] += g;
      }
      if (row + 1 < grid.height) {
        const float g = wf * (x[p + w] - x[p]);
        y[p] -= g;
        y[p + w] += g;
      }
    }
}

void addLaplacianDiagonal(const GridSize& grid, double weight, float* diagonal) {
  const size_t w = size_t(grid.width);
  for (int row = 0; row < grid.height; ++row)
    for (int col = 0; col < grid.width; ++col) {
      const size_t p = size_t(row) * w + size_t(col);
      if (col + 1 < grid.width) {
        diagonal[p] += float(weight);
        diagonal[p + 1] += float(weight);
      }
      if (row + 1 < grid.height) {
        diagonal[p] += float(weight);
        diagonal[p + w] += float(weight);
      }
    }
}

double gradientEnergy(const GridSize& grid, const float* x) {
  const size_t w = size_t(grid.width);
  double sum = 0.0;
  for (int row = 0; row < grid.height; ++row)
    for (int col = 0; col < grid.width; ++col) {
      const size_t p = size_t(row) * w + size_t(col);
      if (col + 1 < grid.width) sum += double(x[p + 1] - x[p]) * double(x[p + 1] - x[p]);
      if (row + 1 < grid.height) sum += double(x[p + w] - x[p]) * double(x[p + w] - x[p]);
    }
  return sum;
}

CgResult solveConjugateGradient(const std::function<void(const float*, float*)>& apply,
                                const std::vector<float>& diagonal, const std::vector<float>& b,
                                std::vector<float>& x, int maxIterations, double tolerance) {
  const size_t n = b.size();
  const double bNorm = std::sqrt(dot(b, b));
  if (bNorm == 0.0) {
    x.assign(n, 0.0f);
    return {};
  }
  std::vector<float> r(n), z(n), p(n), q(n);
  apply(x.data(), q.data());
  for (size_t i = 0; i < n; ++i) r[i] = b[i] - q[i];
  for (size_t i = 0; i < n; ++i) z[i] = r[i] / diagonal[i];
  p = z;
  double rz = dot(r, z);
  CgResult result;
  result.relativeResidual = std::sqrt(dot(r, r)) / bNorm;
  while (result.iterations < maxIterations && result.relativeResidual > tolerance) {
    apply(p.data(), q.data());
    const double pq = dot(p, q);
    if (!(pq > 0.0)) break;  // p is (numerically) in A's null space: nothing left to gain
    const float step = float(rz / pq);
    for (size_t i = 0; i < n; ++i) {
      x[i] += step * p[i];
      r[i] -= step * q[i];
    }
    for (size_t i = 0; i < n; ++i) z[i] = r[i] / diagonal[i];
    const double rzNext = dot(r, z);
    const float beta = float(rzNext / rz);
    rz = rzNext;
    for (size_t i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
    ++result.iterations;
    result.relativeResidual = std::sqrt(dot(r, r)) / bNorm;
  }
  return result;
}

}  // namespace pluvia::derain
