// SPDX-License-Identifier: MIT
// In a program built on the nodes library (as bsdeform-run and the viewer are), CHOLMOD's OpenMP
// regions reach the core's GOMP_parallel inside libbsdeform_nodes (base/Parallel.cpp), ahead of
// libgomp's: the dynamic linker's binding, which the core's own tests cannot see.
#include <dlfcn.h>

#include <Eigen/SparseCore>
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "bsdeform/base/Parallel.h"
#include "bsdeform/dynamics/SparseCholesky.h"

TEST_CASE("Nodes library: CHOLMOD's OpenMP regions bind to the core's GOMP_parallel and run on the caller", "[nodes]") {
  void* entry = dlsym(RTLD_DEFAULT, "GOMP_parallel");
  REQUIRE(entry != nullptr);
  Dl_info info;
  REQUIRE(dladdr(entry, &info) != 0);
  REQUIRE(info.dli_fname != nullptr);
  CHECK(std::string(info.dli_fname).find("libbsdeform_nodes") != std::string::npos);
  // a factorisation of a 2-D Laplacian with three unknowns per point: its supernodes' loops
  constexpr int n = 20, N = 3 * n * n;
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int c = 0; c < 3; ++c) {
        const int k = 3 * (i * n + j) + c;
        t.emplace_back(k, k, 4.5);
        if (i + 1 < n) t.emplace_back(k + 3 * n, k, -1.0);
        if (j + 1 < n) t.emplace_back(k + 3, k, -1.0);
      }
  Eigen::SparseMatrix<double> K(N, N);
  K.setFromTriplets(t.begin(), t.end());
  const long long before = bsdeform::openMpRegionsRunOnCaller();
  bsdeform::SparseCholesky chol;
  REQUIRE(chol.factor(K));
  CHECK(bsdeform::openMpRegionsRunOnCaller() > before);
}
