// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/SparseCholesky.h"

#include <cholmod.h>

#include <algorithm>
#include <cassert>
#include <stdexcept>
#include <string>

#include "bsdeform/base/Parallel.h"

namespace bsdeform {

struct SparseCholesky::Cholmod {
  cholmod_common common;
  cholmod_factor* L = nullptr;
  /// tril(P K Pᵀ): the matrix cholmod_super_numeric factorises (values gathered from K)
  cholmod_sparse* S = nullptr;
  Cholmod() {
    cholmod_start(&common);
    common.print = 0;  // an indefinite tangent is expected, not news
    // as Eigen's CholmodSupernodalLLT: a supernodal LLᵀ kept as it is made
    common.final_asis = 1;
    common.supernodal = CHOLMOD_SUPERNODAL;
  }
  ~Cholmod() {
    clear();
    cholmod_finish(&common);
  }
  void clear() {
    cholmod_free_factor(&L, &common);
    cholmod_free_sparse(&S, &common);
  }
};

namespace {

/// K's lower triangle as CHOLMOD's symmetric (stype -1) matrix, no copy.
cholmod_sparse view(const Eigen::SparseMatrix<double>& K) {
  cholmod_sparse a{};
  a.nrow = size_t(K.rows());
  a.ncol = size_t(K.cols());
  a.nzmax = size_t(K.nonZeros());
  a.p = const_cast<int*>(K.outerIndexPtr());
  a.i = const_cast<int*>(K.innerIndexPtr());
  a.x = const_cast<double*>(K.valuePtr());
  a.stype = -1;
  a.itype = CHOLMOD_INT;
  a.xtype = CHOLMOD_REAL;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  return a;
}

[[noreturn]] void fail(const cholmod_common& c, const char* what) {
  throw std::runtime_error(std::string("CHOLMOD: ") + what + " failed (status " + std::to_string(c.status) + ")");
}

}  // namespace

SparseCholesky::SparseCholesky(Ordering ordering) : m_c(std::make_unique<Cholmod>()) {
  if (ordering != Ordering::Default) {
    m_c->common.nmethods = 1;
    m_c->common.method[0].ordering = ordering == Ordering::Metis ? CHOLMOD_METIS : CHOLMOD_NESDIS;
    m_c->common.postorder = 1;
  }
}

SparseCholesky::~SparseCholesky() = default;

void SparseCholesky::analyse(const Eigen::SparseMatrix<double>& K) {
  cholmod_common& c = m_c->common;
  m_c->clear();
  m_isFactored = false;
  m_outer.clear();
  m_inner.clear();
  cholmod_sparse a = view(K);
  m_c->L = cholmod_analyze(&a, &c);
  if (!m_c->L) fail(c, "the symbolic analysis");
  // The two permuted transposes cholmod_factorize makes of a lower triangle (A2 = triu(P K Pᵀ),
  // then S = tril(A2ᵀ)), run once on a copy of K whose values are their own indices: S's values
  // say where each of its entries comes from in K (indices below 2^53 are exact doubles, and a
  // transpose only moves values).
  const Eigen::Index nnz = K.nonZeros();
  std::vector<double> index(static_cast<size_t>(nnz));
  for (Eigen::Index k = 0; k < nnz; ++k) index[size_t(k)] = double(k);
  a.x = index.data();
  cholmod_sparse* upper = cholmod_ptranspose(&a, 2, static_cast<int*>(m_c->L->Perm), nullptr, 0, &c);
  if (!upper) fail(c, "the permuted transpose");
  m_c->S = cholmod_ptranspose(upper, 2, nullptr, nullptr, 0, &c);
  cholmod_free_sparse(&upper, &c);
  if (!m_c->S) fail(c, "the transpose");
  const int* Sp = static_cast<const int*>(m_c->S->p);
  const size_t sn = size_t(Sp[m_c->S->ncol]);
  // (entries above the diagonal, where a caller passes both triangles, are left out as
  // cholmod_factorize leaves them)
  const double* Sx = static_cast<const double*>(m_c->S->x);
  m_gather.resize(sn);
  for (size_t j = 0; j < sn; ++j) m_gather[j] = int(Sx[j]);
  m_outer.assign(K.outerIndexPtr(), K.outerIndexPtr() + K.outerSize() + 1);
  m_inner.assign(K.innerIndexPtr(), K.innerIndexPtr() + nnz);
  ++m_analyses;
}

bool SparseCholesky::factor(const Eigen::SparseMatrix<double>& K) {
  if (!K.isCompressed() || K.rows() != K.cols())
    throw std::invalid_argument("SparseCholesky::factor: the matrix must be square and compressed");
  const SerialOpenMp serial;  // CHOLMOD's fixed 4-thread regions cost more than they save here
  m_isFactored = false;
  const int* o = K.outerIndexPtr();
  const int* i = K.innerIndexPtr();
  const size_t columns = size_t(K.outerSize()) + 1, nnz = size_t(K.nonZeros());
  if (!m_c->L || m_outer.size() != columns || m_inner.size() != nnz || !std::equal(m_outer.begin(), m_outer.end(), o) ||
      !std::equal(m_inner.begin(), m_inner.end(), i))
    analyse(K);
  double* Sx = static_cast<double*>(m_c->S->x);
  const double* Kx = K.valuePtr();
  const int* g = m_gather.data();
  for (size_t j = 0, m = m_gather.size(); j < m; ++j) Sx[j] = Kx[g[j]];
  double beta[2] = {0.0, 0.0};
  cholmod_common& c = m_c->common;
  if (!cholmod_super_numeric(m_c->S, nullptr, beta, m_c->L, &c)) fail(c, "the numeric factorisation");
  // not positive definite: CHOLMOD_NOT_POSDEF, L->minor the failing column
  m_isFactored = c.status == CHOLMOD_OK && m_c->L->minor == m_c->L->n;
  return m_isFactored;
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::Ref<const Eigen::MatrixXd>& B) {
  assert(m_isFactored && "SparseCholesky::solve without a successful factorisation");
  assert(B.rows() == Eigen::Index(m_c->L->n) && "SparseCholesky::solve: the right-hand side's size");
  cholmod_common& c = m_c->common;
  cholmod_dense b{};
  b.nrow = size_t(B.rows());
  b.ncol = size_t(B.cols());
  b.d = size_t(B.outerStride());
  b.nzmax = b.d * b.ncol;
  b.x = const_cast<double*>(B.data());
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* X = cholmod_solve(CHOLMOD_A, m_c->L, &b, &c);
  if (!X) fail(c, "the solve");
  Eigen::MatrixXd out = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(X->x), B.rows(), B.cols());
  cholmod_free_dense(&X, &c);
  return out;
}

double SparseCholesky::factorNonZeros() const { return m_c->L ? m_c->common.lnz : -1.0; }
double SparseCholesky::factorFlops() const { return m_c->L ? m_c->common.fl : -1.0; }

}  // namespace bsdeform
