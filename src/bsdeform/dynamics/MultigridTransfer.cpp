// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/MultigridTransfer.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "bsdeform/base/HugePages.h"

namespace bsdeform::multigrid {

Transfer1D identityTransfer(int n) {
  Transfer1D t;
  t.children.resize(size_t(n));
  t.parents.resize(size_t(n));
  for (int i = 0; i < n; ++i) t.children[size_t(i)] = t.parents[size_t(i)] = {{i, 1.0}};
  t.taps = {1.0};
  t.fineSize = n;
  return t;
}

bool subdivisionTransfer(const MultigridDirection& dir, int degree, Transfer1D& t) {
  const int nf = dir.size();
  std::vector<double> w(size_t(degree + 2));
  w[0] = std::ldexp(1.0, -degree);
  for (int k = 1; k <= degree + 1; ++k) w[size_t(k)] = w[size_t(k - 1)] * double(degree + 2 - k) / double(k);
  int jmin, jmax;
  if (dir.periodic) {
    jmin = 0;
    jmax = (nf + 1) / 2 - 1;
    if (jmax + 1 <= 2 * degree + 2) return false;
  } else {
    jmin = dir.clampedMin ? 0 : -((degree + 1) / 2);
    jmax = dir.clampedMax ? (nf - 1 - (degree + 1)) / 2 : (nf - 1) / 2;
    if (jmax - jmin + 1 < degree + 2 || jmax - jmin + 1 >= nf) return false;
  }
  t.children.assign(size_t(jmax - jmin + 1), {});
  t.parents.assign(size_t(nf), {});
  t.taps = w;
  t.stride = 2;
  t.first = 2 * jmin;
  t.fineSize = nf;
  t.periodic = dir.periodic;
  for (int j = jmin; j <= jmax; ++j)
    for (int k = 0; k <= degree + 1; ++k) {
      int f = 2 * j + k;
      if (dir.periodic) f %= nf;
      if (f < 0 || f >= nf) continue;
      t.children[size_t(j - jmin)].emplace_back(f, w[size_t(k)]);
      t.parents[size_t(f)].emplace_back(j - jmin, w[size_t(k)]);
    }
  return true;
}

BandMatrix galerkin(const BandMatrix& B, const Transfer1D& t) {
  const int nc = t.coarseSize();
  auto offset = [&](int i, int j) {
    int d = j - i;
    if (B.periodic()) {
      d = ((d % nc) + nc) % nc;
      if (d > nc / 2) d -= nc;
    }
    return d;
  };
  auto forEach = [&](auto&& fn) {
    for (int i = 0; i < nc; ++i)
      for (const auto& [f, wf] : t.children[size_t(i)])
        for (int d = -B.bandwidth(); d <= B.bandwidth(); ++d) {
          const int g = B.column(f, d);
          const double v = B.at(f, d);
          if (g < 0 || v == 0.0) continue;
          for (const auto& [j, wg] : t.parents[size_t(g)]) fn(i, j, wf * v * wg);
        }
  };
  int bw = 0;
  forEach([&](int i, int j, double) { bw = std::max(bw, std::abs(offset(i, j))); });
  BandMatrix C(nc, bw, B.periodic());
  forEach([&](int i, int j, double v) { C.at(i, offset(i, j)) += v; });
  return C;
}

namespace {

/// s = P^T f for one row in the direction of `t` (3 values per point): the row, padded by
/// K - 1 points each side (zeros; when periodic the right side holds the row's first points
/// again, and the left side is never sampled), filtered by the taps at every position, then
/// sampled at the coarse functions' positions.
void restrictRow(const double* f, const Transfer1D& t, std::vector<double>& pad, std::vector<double>& filtered,
                 double* s) {
  const int K = int(t.taps.size()), nf = t.fineSize;
  assert(K >= 1 && K <= kMaxTaps);
  const long halo = 3L * (K - 1);
  pad.assign(size_t(3L * nf + 2 * halo), 0.0);
  std::copy(f, f + 3L * nf, pad.begin() + halo);
  if (t.periodic) std::copy(f, f + halo, pad.begin() + halo + 3L * nf);  // positions nf .. nf + K - 2
  filtered.resize(size_t(3L * nf + halo));
  const double* rows[kMaxTaps];
  for (int k = 0; k < K; ++k) rows[k] = pad.data() + 3L * k;
  // filtered(q) = sum_k taps[k] f(q - (K - 1) + k)
  combineRows(rows, t.taps.data(), K, long(filtered.size()), filtered.data(), false);
  for (int i = 0; i < t.coarseSize(); ++i) {
    const double* q = filtered.data() + 3L * (t.stride * i + t.first + K - 1);
    s[3 * i] = q[0];
    s[3 * i + 1] = q[1];
    s[3 * i + 2] = q[2];
  }
}

/// f += P s for one row in the direction of `t`: the coarse values placed at their positions
/// (zeros between, K - 1 points of halo before, wrapped when periodic), filtered by the taps.
void prolongRow(const double* s, const Transfer1D& t, std::vector<double>& placed, double* f) {
  const int K = int(t.taps.size()), nf = t.fineSize;
  assert(K >= 1 && K <= kMaxTaps);
  const long halo = 3L * (K - 1);
  placed.assign(size_t(3L * nf + halo), 0.0);
  for (int i = 0; i < t.coarseSize(); ++i) {
    double* q = placed.data() + halo + 3L * (t.stride * i + t.first);
    q[0] = s[3 * i];
    q[1] = s[3 * i + 1];
    q[2] = s[3 * i + 2];
  }
  if (t.periodic) std::copy(placed.end() - halo, placed.end(), placed.begin());  // positions -(K - 1) .. -1
  const double* rows[kMaxTaps];
  for (int k = 0; k < K; ++k) rows[k] = placed.data() + halo - 3L * k;
  // f(b) += sum_k taps[k] placed(b - k)
  combineRows(rows, t.taps.data(), K, 3L * nf, f, true);
}

}  // namespace

void restrictTo(const ControlNet& in, const Transfer1D& tu, const Transfer1D& tv, TransferScratch& scratch,
                ControlNet& out) {
  const int muFine = int(tu.parents.size()), nvc = tv.coarseSize(), nuc = tu.coarseSize();
  const long len = 3L * nvc;
  scratch.row.resize(size_t(len));
  allocateNet(out, Eigen::Index(nuc) * nvc);
  out.setZero();
  double* s = scratch.row.data();
  for (int a = 0; a < muFine; ++a) {
    restrictRow(in.data() + 3L * a * tv.fineSize, tv, scratch.pad, scratch.filtered, s);
    for (const auto& [i, w] : tu.parents[size_t(a)]) {
      double* o = out.data() + long(i) * len;
      for (long m = 0; m < len; ++m) o[m] += w * s[m];
    }
  }
}

void prolongAdd(const ControlNet& in, const Transfer1D& tu, const Transfer1D& tv, TransferScratch& scratch,
                ControlNet& out) {
  const int muFine = int(tu.parents.size()), nvc = tv.coarseSize();
  const long len = 3L * nvc;
  scratch.row.resize(size_t(len));
  double* s = scratch.row.data();
  for (int a = 0; a < muFine; ++a) {
    std::fill(s, s + len, 0.0);
    for (const auto& [i, w] : tu.parents[size_t(a)]) {
      const double* c = in.data() + long(i) * len;
      for (long m = 0; m < len; ++m) s[m] += w * c[m];
    }
    prolongRow(s, tv, scratch.pad, out.data() + 3L * a * tv.fineSize);
  }
}

}  // namespace bsdeform::multigrid
