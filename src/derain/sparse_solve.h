#pragma once
// The sparse pieces of Eq. (1)'s quadratic sub-problems on a W x H pixel grid, applied without
// forming a matrix, and the conjugate-gradient solver they feed.
//  - Directional smoothness: (G a)_p = dx (a_{p+x} - a_p) + dy (a_{p+y} - a_p), the forward-
//    difference form of grad a . D0 with D0 = (dx, dy); a term exists where its neighbours do.
//  - Gradient smoothness: |grad s|^2 with forward differences in x and y (the 4-neighbour graph
//    Laplacian as its Gram matrix).
#include <functional>
#include <vector>

namespace pluvia::derain {

struct GridSize {
  int width = 0;
  int height = 0;
  size_t count() const { return size_t(width) * size_t(height); }
};

// y += weight * G^T G x, and its diagonal added to `diagonal`; ||G x||^2.
void addDirectionalGram(const GridSize& grid, double dx, double dy, double weight, const float* x,
                        float* y);
void addDirectionalGramDiagonal(const GridSize& grid, double dx, double dy, double weight,
                                float* diagonal);
double directionalEnergy(const GridSize& grid, double dx, double dy, const float* x);

// y += weight * L x (L = grad^T grad), and its diagonal; |grad x|^2.
void addLaplacian(const GridSize& grid, double weight, const float* x, float* y);
void addLaplacianDiagonal(const GridSize& grid, double weight, float* diagonal);
double gradientEnergy(const GridSize& grid, const float* x);

struct CgResult {
  int iterations = 0;
  double relativeResidual = 0.0;  // |b - A x| / |b| at exit (0 when b = 0)
};

// Solves A x = b for a symmetric positive definite A given as `apply(x, y)`: y = A x, with the
// Jacobi preconditioner diag(A) (every entry must be > 0). `x` holds the starting guess and
// receives the solution. Stops at `tolerance` relative residual or `maxIterations`.
CgResult solveConjugateGradient(const std::function<void(const float*, float*)>& apply,
                                const std::vector<float>& diagonal, const std::vector<float>& b,
                                std::vector<float>& x, int maxIterations, double tolerance);

}  // namespace pluvia::derain
