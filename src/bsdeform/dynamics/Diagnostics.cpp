// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/Diagnostics.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <vector>

#include "bsdeform/base/Multiversion.h"
#include "bsdeform/base/Parallel.h"

namespace bsdeform {

namespace {

// Vector extensions of Multiversion.h: four doubles per vector, AVX2 in the avx2 clone. The core
// is compiled without FP contraction and the reductions are summed in four lanes in a fixed
// order, so every clone gives the same bits.
using simd::load4;
using simd::splat;
using simd::store4;
using simd::v4;
BSDEFORM_INLINE double sum4(v4 x) { return (x[0] + x[1]) + (x[2] + x[3]); }

constexpr int kTaps = 2 * kMaxDegree + 1;
// Rows per block of the sums. Blocks are summed separately and then added in block order, so
// the result does not depend on how many threads computed them.
constexpr int kDiagnosticBlockRows = 32;

// dst = a - b over len entries.
BSDEFORM_MULTIVERSION
void difference(const double* __restrict a, const double* __restrict b, double* __restrict dst, long len) {
  for (long m = 0; m < len; ++m) dst[m] = a[m] - b[m];
}

// The u pass of a row with Toeplitz coefficients: z_p[m] = g[p][0] d0[m] + sum_{t=1..N}
// g[p][t] (up[t][m] + down[t][m]) for p = 0, 1, 2 (the rows t layers above and below; a row of
// zeros where there is none), and the sums of d0^2 and (cur - prev)^2 over the same entries.
template <int N>
BSDEFORM_INLINE void uPassFoldedN(const double* d0, const double* const* up, const double* const* down,
                                  const double (*g)[kTaps], const double* cur, const double* prev, long len, double* z0,
                                  double* z1, double* z2, double* sums) {
  v4 sd = splat(0.0), sv = splat(0.0);
  long m = 0;
  for (; m + 4 <= len; m += 4) {
    const v4 d = load4(d0 + m);
    v4 a0 = splat(g[0][0]) * d, a1 = splat(g[1][0]) * d, a2 = splat(g[2][0]) * d;
    for (int t = 1; t <= N; ++t) {
      const v4 s = load4(up[t] + m) + load4(down[t] + m);
      a0 += splat(g[0][t]) * s;
      a1 += splat(g[1][t]) * s;
      a2 += splat(g[2][t]) * s;
    }
    store4(z0 + m, a0);
    store4(z1 + m, a1);
    store4(z2 + m, a2);
    const v4 v = load4(cur + m) - load4(prev + m);
    sd += d * d;
    sv += v * v;
  }
  double td = 0.0, tv = 0.0;
  for (; m < len; ++m) {
    const double d = d0[m];
    double a0 = g[0][0] * d, a1 = g[1][0] * d, a2 = g[2][0] * d;
    for (int t = 1; t <= N; ++t) {
      const double s = up[t][m] + down[t][m];
      a0 += g[0][t] * s;
      a1 += g[1][t] * s;
      a2 += g[2][t] * s;
    }
    z0[m] = a0;
    z1[m] = a1;
    z2[m] = a2;
    const double v = cur[m] - prev[m];
    td += d * d;
    tv += v * v;
  }
  sums[0] = sum4(sd) + td;
  sums[1] = sum4(sv) + tv;
}

BSDEFORM_MULTIVERSION
void uPassFolded(int n, const double* d0, const double* const* up, const double* const* down, const double (*g)[kTaps],
                 const double* cur, const double* prev, long len, double* z0, double* z1, double* z2, double* sums) {
  switch (n) {
#define BSDEFORM_CASE(N) \
  case N: return uPassFoldedN<N>(d0, up, down, g, cur, prev, len, z0, z1, z2, sums);
    BSDEFORM_CASE(1) BSDEFORM_CASE(2) BSDEFORM_CASE(3) BSDEFORM_CASE(4) BSDEFORM_CASE(5) BSDEFORM_CASE(6)
    BSDEFORM_CASE(7)
#undef BSDEFORM_CASE
  }
}

// The v pass over interior columns, fused with the products: y_q = g[q][0] d[m] + sum_e g[q][e]
// (d[m + 3e] + d[m - 3e]); acc += (z1 y0, z0 y1, z1 y1, z2 y0, z0 y2) (DiagnosticSums order).
template <int N>
BSDEFORM_INLINE void vPassProductsN(const double* d, const double (*g)[kTaps], const double* z0, const double* z1,
                                    const double* z2, long len, double* acc) {
  v4 t0 = splat(0.0), t1 = t0, t2 = t0, t3 = t0, t4 = t0;
  long m = 0;
  for (; m + 4 <= len; m += 4) {
    const v4 c = load4(d + m);
    v4 y0 = splat(g[0][0]) * c, y1 = splat(g[1][0]) * c, y2 = splat(g[2][0]) * c;
    for (int e = 1; e <= N; ++e) {
      const v4 r = load4(d + m + 3 * e) + load4(d + m - 3 * e);
      y0 += splat(g[0][e]) * r;
      y1 += splat(g[1][e]) * r;
      y2 += splat(g[2][e]) * r;
    }
    const v4 a0 = load4(z0 + m), a1 = load4(z1 + m), a2 = load4(z2 + m);
    t0 += a1 * y0;
    t1 += a0 * y1;
    t2 += a1 * y1;
    t3 += a2 * y0;
    t4 += a0 * y2;
  }
  double s[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
  for (; m < len; ++m) {
    const double c = d[m];
    double y0 = g[0][0] * c, y1 = g[1][0] * c, y2 = g[2][0] * c;
    for (int e = 1; e <= N; ++e) {
      const double r = d[m + 3 * e] + d[m - 3 * e];
      y0 += g[0][e] * r;
      y1 += g[1][e] * r;
      y2 += g[2][e] * r;
    }
    s[0] += z1[m] * y0;
    s[1] += z0[m] * y1;
    s[2] += z1[m] * y1;
    s[3] += z2[m] * y0;
    s[4] += z0[m] * y2;
  }
  acc[0] += sum4(t0) + s[0];
  acc[1] += sum4(t1) + s[1];
  acc[2] += sum4(t2) + s[2];
  acc[3] += sum4(t3) + s[3];
  acc[4] += sum4(t4) + s[4];
}

BSDEFORM_MULTIVERSION
void vPassProducts(int n, const double* d, const double (*g)[kTaps], const double* z0, const double* z1,
                   const double* z2, long len, double* acc) {
  switch (n) {
#define BSDEFORM_CASE(N) \
  case N: return vPassProductsN<N>(d, g, z0, z1, z2, len, acc);
    BSDEFORM_CASE(1) BSDEFORM_CASE(2) BSDEFORM_CASE(3) BSDEFORM_CASE(4) BSDEFORM_CASE(5) BSDEFORM_CASE(6)
    BSDEFORM_CASE(7)
#undef BSDEFORM_CASE
  }
}

}  // namespace

DiagnosticPass::DiagnosticPass(const SplineSpace& space, const StiffnessStencil& stencil, const ControlNet& current,
                               const ControlNet& rest, const ControlNet& previous, const double* mass)
    : m_space(&space),
      m_gu(&stencil.gramU()),
      m_current(current.data()),
      m_rest(rest.data()),
      m_previous(previous.data()),
      m_mass(mass) {
  assert(current.rows() == space.netSize() && rest.rows() == space.netSize() && previous.rows() == space.netSize());
  const SplineSpace& s = space;
  const GramRows1D& gv = stencil.gramV();
  const int n1 = s.degreeU(), n2 = s.degreeV(), cols = s.netCols();
  const LayerRange mv = s.movingV();
  // Columns. Interior: Toeplitz rows of G_v (type 0) whose neighbourhood lies in the net (no
  // periodic wrap), a contiguous range [jb, je) done by vPassProducts; the others one by one.
  auto neighbourV = [&](int l) {
    if (s.periodicV() && l >= cols) l -= mv.count;
    return (l >= 0 && l < cols) ? l : -1;
  };
  auto interiorColumn = [&](int j) { return gv.rowType(j) == 0 && j - n2 >= 0 && j + n2 < cols; };
  int jb = mv.first;
  while (jb < mv.first + mv.count && !interiorColumn(jb)) ++jb;
  int je = jb;
  while (je < mv.first + mv.count && interiorColumn(je)) ++je;
  m_jb = jb;
  m_je = je;
  for (int j = mv.first; j < mv.first + mv.count; ++j) {
    if (j >= jb && j < je) continue;
    BandColumn c;
    c.j = j;
    for (int e = -n2; e <= n2; ++e) {
      c.neighbour[e + n2] = neighbourV(j + e);
      for (int q = 0; q < 3; ++q) c.g[q][e + n2] = gv.entry(q, gv.rowType(j), e);
    }
    m_bandColumns.push_back(c);
  }
  for (int q = 0; q < 3; ++q) {
    for (int e = 0; e <= n2; ++e) m_gvInterior[q][e] = gv.entry(q, 0, e);
    for (int t = 0; t <= n1; ++t) m_guInterior[q][t] = m_gu->entry(q, 0, t);
  }
  m_partial.resize(size_t(std::max(blocks(), 1)));
}

int DiagnosticPass::blocks() const {
  return (m_space->movingU().count + kDiagnosticBlockRows - 1) / kDiagnosticBlockRows;
}

void DiagnosticPass::computeBlock(int b) {
  assert(b >= 0 && b < blocks());
  const LayerRange mu = m_space->movingU();
  m_partial[size_t(b)].sums = blockSums(mu.first + b * kDiagnosticBlockRows,
                                   mu.first + std::min(mu.count, (b + 1) * kDiagnosticBlockRows));
}

DiagnosticSums DiagnosticPass::sums() const {
  // blocks added in block order: the same bits whichever thread computed them
  DiagnosticSums total = m_partial[0].sums;
  for (size_t b = 1; b < m_partial.size(); ++b) {
    const DiagnosticSums& p = m_partial[b].sums;
    for (int k = 0; k < 5; ++k) total.terms[k] += p.terms[k];
    total.displacement += p.displacement;
    total.velocity += p.velocity;
  }
  return total;
}

// The sums of the rows [rowBegin, rowEnd), with their own buffers (blocks may run on different
// threads).
DiagnosticSums DiagnosticPass::blockSums(int rowBegin, int rowEnd) const {
  const SplineSpace& s = *m_space;
  const GramRows1D& gu = *m_gu;
  const int n1 = s.degreeU(), n2 = s.degreeV(), rows = s.netRows(), cols = s.netCols();
  const LayerRange mu = s.movingU(), mv = s.movingV();
  const long rowLen = 3L * cols, movBegin = 3L * mv.first, movLen = 3L * mv.count;
  const int jb = m_jb, je = m_je;
  const double* current = m_current;
  const double* rest = m_rest;
  const double* previous = m_previous;
  const double* mass = m_mass;

  // Net layer of neighbour layer l, or -1 (as StiffnessStencil::neighbourU).
  auto neighbourU = [&](int l) {
    if (s.periodicU() && l >= rows) l -= mu.count;
    return (l >= 0 && l < rows) ? l : -1;
  };
  // D = current - rest of the net layers i - n1 .. i + n1 in a ring, keyed by the layer before
  // the periodic wrap (consecutive keys, different slots).
  const int slots = 2 * n1 + 1;
  std::vector<double> ring(size_t(slots) * rowLen);
  std::vector<int> key(size_t(slots), -1);
  auto dRow = [&](int unwrapped) -> const double* {  // null: no such layer
    const int l = neighbourU(unwrapped);
    if (l < 0) return nullptr;
    const int slot = unwrapped % slots;
    double* d = ring.data() + size_t(slot) * rowLen;
    if (key[size_t(slot)] != unwrapped) {
      key[size_t(slot)] = unwrapped;
      difference(current + long(l) * rowLen, rest + long(l) * rowLen, d, rowLen);
    }
    return d;
  };
  const std::vector<double> zeros(size_t(rowLen), 0.0);  // the layers beyond the net
  std::vector<double> z(3 * size_t(movLen));
  double* z0 = z.data();
  double* z1 = z0 + movLen;
  double* z2 = z1 + movLen;

  DiagnosticSums out;
  for (int i = rowBegin; i < rowEnd; ++i) {
    const double* d = dRow(i);
    const double* up[kMaxDegree + 1] = {nullptr};
    const double* down[kMaxDegree + 1] = {nullptr};
    for (int t = 1; t <= n1; ++t) {
      down[t] = i - t >= 0 ? dRow(i - t) : nullptr;
      up[t] = dRow(i + t);
    }
    // Z_p = (G_u^p D) on this row's moving columns, with the sums of |D|^2 and |velocity|^2
    const long start = long(i) * rowLen + movBegin;
    const int typeU = gu.rowType(i);
    double sums[2];
    if (typeU == 0) {
      const double* upM[kMaxDegree + 1] = {nullptr};
      const double* downM[kMaxDegree + 1] = {nullptr};
      for (int t = 1; t <= n1; ++t) {
        upM[t] = (up[t] ? up[t] : zeros.data()) + movBegin;
        downM[t] = (down[t] ? down[t] : zeros.data()) + movBegin;
      }
      uPassFolded(n1, d + movBegin, upM, downM, m_guInterior, current + start, previous + start, movLen, z0,
                  z1, z2, sums);
    } else {  // a row of a FREE side's outer layers: truncated integrals, not symmetric
      double g[3][kTaps];
      const double* nb[kTaps];
      for (int t = -n1; t <= n1; ++t) {
        nb[t + n1] = t == 0 ? d : t > 0 ? up[t] : down[-t];
        for (int p = 0; p < 3; ++p) g[p][t + n1] = gu.entry(p, typeU, t);
      }
      sums[0] = sums[1] = 0.0;
      for (long m = 0; m < movLen; ++m) {
        double a[3] = {0.0, 0.0, 0.0};
        for (int t = 0; t <= 2 * n1; ++t)
          if (nb[t])
            for (int p = 0; p < 3; ++p) a[p] += g[p][t] * nb[t][movBegin + m];
        z0[m] = a[0];
        z1[m] = a[1];
        z2[m] = a[2];
        const double dm = d[movBegin + m], v = current[start + m] - previous[start + m];
        sums[0] += dm * dm;
        sums[1] += v * v;
      }
    }
    out.displacement += sums[0];
    if (!mass) {
      out.velocity += sums[1];
    } else {
      const double* m = mass + long(i - mu.first) * mv.count;
      const double* c = current + start;
      const double* p = previous + start;
      double vv = 0.0;
      for (int b = 0; b < mv.count; ++b) {
        const double vx = c[3 * b] - p[3 * b], vy = c[3 * b + 1] - p[3 * b + 1], vz = c[3 * b + 2] - p[3 * b + 2];
        vv += m[b] * (vx * vx + vy * vy + vz * vz);
      }
      out.velocity += vv;
    }
    // Y_q = (G_v^q D) on the same entries, and the products Z_p . Y_q
    const long zOffset = 3L * (jb - mv.first);
    vPassProducts(n2, d + 3L * jb, m_gvInterior, z0 + zOffset, z1 + zOffset, z2 + zOffset, 3L * (je - jb), out.terms);
    for (const BandColumn& c : m_bandColumns) {
      const long zc = 3L * (c.j - mv.first);
      for (int k = 0; k < 3; ++k) {
        double y[3] = {0.0, 0.0, 0.0};
        for (int e = 0; e <= 2 * n2; ++e) {
          if (c.neighbour[e] < 0) continue;
          const double x = d[3L * c.neighbour[e] + k];
          for (int q = 0; q < 3; ++q) y[q] += c.g[q][e] * x;
        }
        out.terms[0] += z1[zc + k] * y[0];
        out.terms[1] += z0[zc + k] * y[1];
        out.terms[2] += z1[zc + k] * y[1];
        out.terms[3] += z2[zc + k] * y[0];
        out.terms[4] += z0[zc + k] * y[2];
      }
    }
  }
  return out;
}

DiagnosticSums diagnosticSums(const SplineSpace& s, const StiffnessStencil& A, const ControlNet& current,
                              const ControlNet& rest, const ControlNet& previous, const double* mass) {
  DiagnosticPass pass(s, A, current, rest, previous, mass);
  const int blocks = pass.blocks();
  if (long(s.movingU().count) * s.movingV().count >= explicitParallelMinPoints()) {
    runParts(blocks, [&pass](int b) { pass.computeBlock(b); });
  } else {
    for (int b = 0; b < blocks; ++b) pass.computeBlock(b);
  }
  return pass.sums();
}

Diagnostics diagnosticsFromSums(const DiagnosticSums& sums, const Weights& w, double massScale, double dt) {
  Diagnostics d;
  d.norm = std::sqrt(sums.displacement);
  d.kinetic = 0.5 * massScale * sums.velocity / (dt * dt);
  StrainEnergy& e = d.strain;
  // the stencil carries 2 w11 (eq. 7): its half is w11
  e.w10 = 0.5 * w.w10 * sums.terms[0];
  e.w01 = 0.5 * w.w01 * sums.terms[1];
  e.w11 = w.w11 * sums.terms[2];
  e.w20 = 0.5 * w.w20 * sums.terms[3];
  e.w02 = 0.5 * w.w02 * sums.terms[4];
  e.total = e.w10 + e.w01 + e.w11 + e.w20 + e.w02;
  return d;
}

}  // namespace bsdeform
