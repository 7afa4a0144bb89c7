// SPDX-License-Identifier: MIT
// The Newton tangent's factorisation (dynamics/SparseCholesky): it solves K x = b, it factorises
// the matrix CHOLMOD's own driver would (the same bits as Eigen's CholmodSupernodalLLT, which the
// steppers used before), its symbolic analysis is kept exactly while the pattern stays, and an
// indefinite matrix is reported, not solved with.
#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>
#include <catch2/catch.hpp>
#include <random>
#include <stdexcept>
#include <vector>

#include "bsdeform/base/Parallel.h"
#include "bsdeform/dynamics/SparseCholesky.h"

using namespace bsdeform;

namespace {

// A symmetric matrix over an n x n grid of points with 3 unknowns each, every pair of points
// within 2 grid steps of each other coupled by a random 3 x 3 block (the pattern of a biquadratic
// spline's tangent), made diagonally dominant (SPD) unless `shift` takes that away. Lower triangle.
Eigen::SparseMatrix<double> gridMatrix(int n, unsigned seed, double shift = 0.0, bool extra = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int N = 3 * n * n;
  std::vector<Eigen::Triplet<double>> t;
  std::vector<double> rowSum(size_t(N), 0.0);
  auto add = [&](int r, int c, double v) {
    if (r < c) std::swap(r, c);
    t.emplace_back(r, c, v);
    if (r != c) {
      rowSum[size_t(r)] += std::abs(v);
      rowSum[size_t(c)] += std::abs(v);
    }
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int di = 0; di <= 2; ++di)
        for (int dj = -2; dj <= 2; ++dj) {
          const int i2 = i + di, j2 = j + dj;
          if (i2 >= n || j2 < 0 || j2 >= n || (di == 0 && dj <= 0)) continue;
          const int p = i * n + j, q = i2 * n + j2;
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) add(3 * q + a, 3 * p + b, u(rng));
        }
  for (int p = 0; p < n * n; ++p)  // the points' own blocks' off-diagonal entries
    for (int a = 1; a < 3; ++a)
      for (int b = 0; b < a; ++b) add(3 * p + a, 3 * p + b, u(rng));
  if (extra) add(N - 1, 0, 0.5);  // a coupling of two far points (as self-contact adds)
  for (int k = 0; k < N; ++k) t.emplace_back(k, k, rowSum[size_t(k)] + 1.0 + shift);
  Eigen::SparseMatrix<double> K(N, N);
  K.setFromTriplets(t.begin(), t.end());
  K.makeCompressed();
  return K;
}

Eigen::MatrixXd full(const Eigen::SparseMatrix<double>& lower) {
  const Eigen::MatrixXd L = Eigen::MatrixXd(lower);
  Eigen::MatrixXd K = L + L.transpose();
  K.diagonal() = L.diagonal();
  return K;
}

}  // namespace

TEST_CASE("SparseCholesky: K x = b solved with the bits of CHOLMOD's own driver", "[core][cholesky]") {
  const Eigen::SparseMatrix<double> K = gridMatrix(12, 7);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd B(K.rows(), 3);
  for (Eigen::Index i = 0; i < B.size(); ++i) B.data()[i] = u(rng);

  SparseCholesky chol;
  REQUIRE(chol.factor(K));
  const Eigen::MatrixXd X = chol.solve(B);
  // the solution: residual at rounding level
  const Eigen::MatrixXd R = full(K) * X - B;
  CHECK(R.cwiseAbs().maxCoeff() < 1e-12 * (full(K).cwiseAbs().maxCoeff() * X.cwiseAbs().maxCoeff()));
  // the same matrix, ordering and supernodes as cholmod_factorize: identical solutions (with
  // this build's single-threaded BLAS; a BLAS whose results depend on its threads or on the
  // CPU's code path would differ by rounding)
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> reference;
  reference.compute(K);
  REQUIRE(reference.info() == Eigen::Success);
  const Eigen::MatrixXd Xr = reference.solve(B);
  CHECK((X - Xr).cwiseAbs().maxCoeff() == 0.0);
  // one right-hand side (CHOLMOD's loops for one column round differently from those for three)
  const Eigen::VectorXd b0 = B.col(0);
  CHECK((chol.solve(b0) - reference.solve(b0)).cwiseAbs().maxCoeff() == 0.0);
  // both triangles given (the static solve's matrices): the upper one is not read
  Eigen::SparseMatrix<double> both = full(K).sparseView();
  both.makeCompressed();
  SparseCholesky fromBoth;
  REQUIRE(fromBoth.factor(both));
  CHECK((fromBoth.solve(B) - X).cwiseAbs().maxCoeff() == 0.0);
  CHECK(chol.factorNonZeros() > double(K.nonZeros()));
  CHECK(chol.factorFlops() > 0.0);
  // the orderings the benchmarks force: the same solution to rounding
  for (const SparseCholesky::Ordering o : {SparseCholesky::Ordering::Metis, SparseCholesky::Ordering::NestedDissection}) {
    SparseCholesky forced(o);
    REQUIRE(forced.factor(K));
    CHECK((forced.solve(B) - X).cwiseAbs().maxCoeff() < 1e-12 * X.cwiseAbs().maxCoeff());
  }
  // an uncompressed matrix is refused (its arrays are not what CHOLMOD reads)
  Eigen::SparseMatrix<double> loose = K;
  loose.uncompress();
  CHECK_THROWS_AS(chol.factor(loose), std::invalid_argument);
}

TEST_CASE("SparseCholesky: the analysis kept while the pattern stays and made again when not", "[core][cholesky]") {
  SparseCholesky chol;
  const Eigen::SparseMatrix<double> K1 = gridMatrix(8, 1), K2 = gridMatrix(8, 2);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(K1.rows(), -1.0, 2.0);
  REQUIRE(chol.factor(K1));
  const Eigen::VectorXd x1 = chol.solve(b);
  REQUIRE(chol.factor(K2));  // other values, the same pattern
  CHECK(chol.analyses() == 1);
  const Eigen::VectorXd x2 = chol.solve(b);
  CHECK((full(K2) * x2 - b).cwiseAbs().maxCoeff() < 1e-11);
  CHECK((x2 - x1).cwiseAbs().maxCoeff() > 1e-3);  // the new values were used
  // a coupling beyond the pattern: a new analysis, and the entry counts
  const Eigen::SparseMatrix<double> K3 = gridMatrix(8, 2, 0.0, true);
  REQUIRE(chol.factor(K3));
  CHECK(chol.analyses() == 2);
  const Eigen::VectorXd x3 = chol.solve(b);
  CHECK((full(K3) * x3 - b).cwiseAbs().maxCoeff() < 1e-11);
  CHECK((x3 - x2).cwiseAbs().maxCoeff() > 1e-8);
  // as many entries in other places (the far coupling moved): analysed again
  Eigen::SparseMatrix<double> K4 = K3;
  {
    std::vector<Eigen::Triplet<double>> t;
    for (Eigen::Index c = 0; c < K3.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(K3, c); it; ++it)
        t.emplace_back(it.row() == K3.rows() - 1 && c == 0 ? it.row() - 1 : it.row(), int(c), it.value());
    K4.setFromTriplets(t.begin(), t.end());
    K4.makeCompressed();
  }
  REQUIRE(K4.nonZeros() == K3.nonZeros());
  REQUIRE(chol.factor(K4));
  CHECK(chol.analyses() == 3);
  CHECK((full(K4) * chol.solve(b) - b).cwiseAbs().maxCoeff() < 1e-11);
  // back to the first pattern: analysed again, solved right
  REQUIRE(chol.factor(K1));
  CHECK(chol.analyses() == 4);
  CHECK((chol.solve(b) - x1).cwiseAbs().maxCoeff() < 1e-13);
}

TEST_CASE("SparseCholesky: an indefinite matrix reported", "[core][cholesky]") {
  SparseCholesky chol;
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(3 * 36);
  CHECK_FALSE(chol.isFactored());
  const Eigen::SparseMatrix<double> bad = gridMatrix(6, 4, -200.0);  // diagonal far below the couplings
  CHECK_FALSE(chol.factor(bad));
  CHECK_FALSE(chol.isFactored());
  const Eigen::SparseMatrix<double> good = gridMatrix(6, 4);
  REQUIRE(chol.factor(good));  // the same pattern: the kept analysis serves after the failure
  CHECK(chol.analyses() == 1);
  CHECK((full(good) * chol.solve(b) - b).cwiseAbs().maxCoeff() < 1e-11);
}

TEST_CASE("SparseCholesky: CHOLMOD's OpenMP regions reach the core's GOMP_parallel and run on the caller",
          "[core][cholesky]") {
  // Debian's CHOLMOD opens an OpenMP region per loop of each supernode; the core's entry
  // (base/Parallel.cpp) must be the one the dynamic linker bound them to
  const Eigen::SparseMatrix<double> K = gridMatrix(16, 5);
  const long long before = openMpRegionsRunOnCaller();
  SparseCholesky chol;
  REQUIRE(chol.factor(K));
  REQUIRE(chol.factor(K));
  CHECK(openMpRegionsRunOnCaller() > before);
}
