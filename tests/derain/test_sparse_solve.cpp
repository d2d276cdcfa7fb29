// The matrix-free pieces of Eq. (1)'s sub-problems against dense matrices built independently
// from their definitions, and conjugate gradients against Eigen's dense LLT.
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "derain/sparse_solve.h"

namespace pluvia::derain {
namespace {

const GridSize kGrid{7, 5};

// Dense G: one row per forward-difference term dx (x[p+1]-x[p]) + dy (x[p+w]-x[p]).
Eigen::MatrixXd denseDirectional(double dx, double dy) {
  const int w = kGrid.width, h = kGrid.height, n = w * h;
  std::vector<Eigen::VectorXd> rows;
  for (int y = 0; y < (dy != 0 ? h - 1 : h); ++y)
    for (int x = 0; x < (dx != 0 ? w - 1 : w); ++x) {
      Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
      const int p = y * w + x;
      if (dx != 0) r[p + 1] += dx, r[p] -= dx;
      if (dy != 0) r[p + w] += dy, r[p] -= dy;
      rows.push_back(r);
    }
  Eigen::MatrixXd g(rows.size(), n);
  for (size_t i = 0; i < rows.size(); ++i) g.row(Eigen::Index(i)) = rows[i].transpose();
  return g;
}

Eigen::MatrixXd denseGradient() {
  const int w = kGrid.width, h = kGrid.height, n = w * h;
  std::vector<Eigen::VectorXd> rows;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int p = y * w + x;
      if (x + 1 < w) {
        Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
        r[p + 1] = 1, r[p] = -1;
        rows.push_back(r);
      }
      if (y + 1 < h) {
        Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
        r[p + w] = 1, r[p] = -1;
        rows.push_back(r);
      }
    }
  Eigen::MatrixXd g(rows.size(), n);
  for (size_t i = 0; i < rows.size(); ++i) g.row(Eigen::Index(i)) = rows[i].transpose();
  return g;
}

std::vector<float> randomVector(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<float> v(kGrid.count());
  for (float& x : v) x = u(rng);
  return v;
}

Eigen::VectorXd toEigen(const std::vector<float>& v) {
  Eigen::VectorXd e(Eigen::Index(v.size()));
  for (size_t i = 0; i < v.size(); ++i) e[Eigen::Index(i)] = v[i];
  return e;
}

TEST(SparseSolve, DirectionalGramMatchesDenseMatrix) {
  for (auto [dx, dy] :
       {std::pair{0.0, -1.0}, std::pair{0.5, -0.866}, std::pair{-0.3, 0.95}, std::pair{1.0, 0.0}}) {
    const Eigen::MatrixXd g = denseDirectional(dx, dy);
    const Eigen::MatrixXd gram = 0.7 * g.transpose() * g;
    const std::vector<float> x = randomVector(1);
    std::vector<float> y(x.size(), 0.0f), diagonal(x.size(), 0.0f);
    addDirectionalGram(kGrid, dx, dy, 0.7, x.data(), y.data());
    addDirectionalGramDiagonal(kGrid, dx, dy, 0.7, diagonal.data());
    EXPECT_LT((toEigen(y) - gram * toEigen(x)).norm(), 1e-5) << dx << "," << dy;
    EXPECT_LT((toEigen(diagonal) - gram.diagonal()).norm(), 1e-5);
    EXPECT_NEAR(directionalEnergy(kGrid, dx, dy, x.data()), (g * toEigen(x)).squaredNorm(), 1e-5);
  }
}

TEST(SparseSolve, LaplacianMatchesDenseMatrix) {
  const Eigen::MatrixXd g = denseGradient();
  const Eigen::MatrixXd laplacian = 0.3 * g.transpose() * g;
  const std::vector<float> x = randomVector(2);
  std::vector<float> y(x.size(), 0.0f), diagonal(x.size(), 0.0f);
  addLaplacian(kGrid, 0.3, x.data(), y.data());
  addLaplacianDiagonal(kGrid, 0.3, diagonal.data());
  EXPECT_LT((toEigen(y) - laplacian * toEigen(x)).norm(), 1e-5);
  EXPECT_LT((toEigen(diagonal) - laplacian.diagonal()).norm(), 1e-5);
  EXPECT_NEAR(gradientEnergy(kGrid, x.data()), (g * toEigen(x)).squaredNorm(), 1e-5);
}

TEST(SparseSolve, ConjugateGradientMatchesDenseSolveOnAStiffSystem) {
  // diag(data) + mu G^T G with data spanning six decades: the stiff case of the alpha step.
  const Eigen::MatrixXd g = denseDirectional(0.2, -0.98);
  std::vector<float> data = randomVector(3);
  for (size_t i = 0; i < data.size(); ++i)
    data[i] = float(std::pow(10.0, -6.0 + 6.0 * std::abs(data[i])));
  const double mu = 1e3;
  const Eigen::MatrixXd a = Eigen::MatrixXd(toEigen(data).asDiagonal()) + mu * g.transpose() * g;
  const std::vector<float> b = randomVector(4);
  const Eigen::VectorXd expected = a.llt().solve(toEigen(b));
  std::vector<float> diagonal = data;
  addDirectionalGramDiagonal(kGrid, 0.2, -0.98, mu, diagonal.data());
  std::vector<float> x(b.size(), 0.0f);
  auto apply = [&](const float* in, float* out) {
    for (size_t p = 0; p < data.size(); ++p) out[p] = data[p] * in[p];
    addDirectionalGram(kGrid, 0.2, -0.98, mu, in, out);
  };
  const CgResult result = solveConjugateGradient(apply, diagonal, b, x, 2000, 1e-7);
  EXPECT_LE(result.relativeResidual, 1e-6);
  EXPECT_LT((toEigen(x) - expected).norm() / expected.norm(), 1e-2);
}

TEST(SparseSolve, ZeroRightHandSideGivesZero) {
  std::vector<float> x(kGrid.count(), 5.0f), diagonal(kGrid.count(), 1.0f), b(kGrid.count(), 0.0f);
  const CgResult result = solveConjugateGradient(
      [](const float* in, float* out) { std::copy(in, in + kGrid.count(), out); }, diagonal, b, x,
      10, 1e-6);
  EXPECT_EQ(result.iterations, 0);
  for (float v : x) EXPECT_EQ(v, 0.0f);
}

}  // namespace
}  // namespace pluvia::derain
