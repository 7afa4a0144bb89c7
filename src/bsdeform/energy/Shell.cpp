// SPDX-License-Identifier: MIT
#include "bsdeform/energy/Shell.h"

#include "bsdeform/base/ParameterError.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <atomic>
#include <utility>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "bsdeform/energy/ShellKinematics.h"
#include "bsdeform/spline/GaussLegendre.h"
#include "bsdeform/base/Multiversion.h"
#include "bsdeform/base/NumberText.h"
#include "bsdeform/base/Parallel.h"

namespace bsdeform {
namespace {

using namespace shell;

constexpr int kMaxPoints = kMaxDegree + 1;
/// (u order, v order) of the five derivatives in y.
constexpr int kOrderU[5] = {1, 0, 2, 1, 0};
constexpr int kOrderV[5] = {0, 1, 0, 1, 2};

/// What one element pass needs: the tables and sizes.
struct Tables {
  int L1, L2, Q1, Q2, cols;
  const double* tu;  // [q][order][a], L1 wide
  const double* tv;
  double u(int q, int d, int a) const { return tu[(q * 3 + d) * L1 + a]; }
  double v(int q, int d, int b) const { return tv[(q * 3 + d) * L2 + b]; }
};

/// One element (e1, e2) with sum factorisation: gathers the net (loader(row, c) -> T), runs
/// the kernel at each Gauss point and adds the gradient to out(row, c, value) when `grad`.
/// Returns the element's energies.
/// LC, QC: the element's points and Gauss points per direction when known at compile time (the
/// same in both directions; 0: read from tb). The loops are the same either way, so are the
/// sums' orders and the results, bit for bit; fixed bounds let the compiler unroll them and keep
/// the element's arrays in registers (ShellForces: docs/benchmarks.md, issue 34).
template <typename T, int LC = 0, int QC = 0, typename Law, typename Load, typename Store>
void elementPass(const Tables& tb, int e1, int e2, const ShellEnergy::RestPoint* rest, const Law& law,
                 bool bending, bool grad, Load&& load, Store&& store, T& em, T& eb) {
  const int L1 = LC ? LC : tb.L1, L2 = LC ? LC : tb.L2, Q1 = QC ? QC : tb.Q1, Q2 = QC ? QC : tb.Q2;
  const auto tbu = [&](int q, int d, int a) { return tb.tu[(q * 3 + d) * L1 + a]; };
  const auto tbv = [&](int q, int d, int b) { return tb.tv[(q * 3 + d) * L2 + b]; };
  // T[a][q2][dv][c] = Σ_b tv[q2][dv][b] X[a][b][c]
  T Tv[kMaxPoints][kMaxPoints][3][3];
  for (int a = 0; a < L1; ++a) {
    T X[kMaxPoints][3];
    const Eigen::Index base = Eigen::Index(e1 + a) * tb.cols + e2;
    for (int b = 0; b < L2; ++b)
      for (int c = 0; c < 3; ++c) X[b][c] = load(base + b, c);
    for (int q2 = 0; q2 < Q2; ++q2)
      for (int d = 0; d < 3; ++d)
        for (int c = 0; c < 3; ++c) {
          T s = T(0.0);
          for (int b = 0; b < L2; ++b) s += tbv(q2, d, b) * X[b][c];
          Tv[a][q2][d][c] = s;
        }
  }
  T U[kMaxPoints][kMaxPoints][3][3];
  if (grad)
    for (int a = 0; a < L1; ++a)
      for (int q2 = 0; q2 < Q2; ++q2)
        for (int d = 0; d < 3; ++d)
          for (int c = 0; c < 3; ++c) U[a][q2][d][c] = T(0.0);
  em = T(0.0);
  eb = T(0.0);
  for (int q1 = 0; q1 < Q1; ++q1)
    for (int q2 = 0; q2 < Q2; ++q2) {
      T y[15];
      for (int m = 0; m < 5; ++m)
        for (int c = 0; c < 3; ++c) {
          T s = T(0.0);
          for (int a = 0; a < L1; ++a) s += tbu(q1, kOrderU[m], a) * Tv[a][q2][kOrderV[m]][c];
          y[3 * m + c] = s;
        }
      T g[15], pm, pb;
      density(y, rest[q1 * Q2 + q2], law, bending, g, pm, pb);
      em += pm;
      eb += pb;
      if (!grad) continue;
      for (int a = 0; a < L1; ++a)
        for (int m = 0; m < 5; ++m) {
          const double w = tbu(q1, kOrderU[m], a);
          for (int c = 0; c < 3; ++c) U[a][q2][kOrderV[m]][c] += w * g[3 * m + c];
        }
    }
  if (!grad) return;
  for (int a = 0; a < L1; ++a) {
    const Eigen::Index base = Eigen::Index(e1 + a) * tb.cols + e2;
    for (int b = 0; b < L2; ++b)
      for (int c = 0; c < 3; ++c) {
        T s = T(0.0);
        for (int q2 = 0; q2 < Q2; ++q2)
          for (int d = 0; d < 3; ++d) s += tbv(q2, d, b) * U[a][q2][d][c];
        store(base + b, c, s);
      }
  }
}

/// elementPass with the loop bounds of the common elements fixed (bicubic and biquadratic with
/// degree + 1 Gauss points per direction), else read at run time.
template <typename T, typename... Args>
void anyElementPass(const Tables& tb, Args&&... args) {
  const bool square = tb.L1 == tb.L2 && tb.Q1 == tb.Q2 && tb.Q1 == tb.L1;
  if (square && tb.L1 == 4)
    elementPass<T, 4, 4>(tb, std::forward<Args>(args)...);
  else if (square && tb.L1 == 3)
    elementPass<T, 3, 3>(tb, std::forward<Args>(args)...);
  else
    elementPass<T>(tb, std::forward<Args>(args)...);
}

/// y at one Gauss point (doubles) and the coefficients c[m][k] of y_m = Σ_k c[m][k] X_k.
void pointCoefficients(const Tables& tb, int q1, int q2, double c[5][kMaxPoints * kMaxPoints]) {
  for (int m = 0; m < 5; ++m)
    for (int a = 0; a < tb.L1; ++a)
      for (int b = 0; b < tb.L2; ++b) c[m][a * tb.L2 + b] = tb.u(q1, kOrderU[m], a) * tb.v(q2, kOrderV[m], b);
}

/// pointCoefficients of every Gauss point of an element (q1 Q2 + q2), the same in every element
/// of a uniform spline: made once per pass over the elements.
struct PointCoefficients {
  double c[5][kMaxPoints * kMaxPoints];
};
std::vector<PointCoefficients> elementCoefficients(const Tables& tb) {
  std::vector<PointCoefficients> out(size_t(tb.Q1) * tb.Q2);
  for (int q1 = 0; q1 < tb.Q1; ++q1)
    for (int q2 = 0; q2 < tb.Q2; ++q2) pointCoefficients(tb, q1, q2, out[size_t(q1 * tb.Q2 + q2)].c);
  return out;
}

/// Ke[p][q] += Σ_d c[d][p] Σ_e c[e][q] H_de (3 x 3 blocks, q >= p) for one Gauss point: the
/// element tangent's inner loops (HC: scratch, 5 L 9). H column-major 15 x 15.
template <int LC>
BSDEFORM_INLINE void accumulateElementBody(int Lrun, const double (*c)[kMaxPoints * kMaxPoints], const double* H,
                                          double* HC, double* Ke) {
  const int L = LC ? LC : Lrun;
  // H's 3 x 3 blocks transposed into row-major [d][e][a][b] once
  double Hb[5][5][9];
  for (int d = 0; d < 5; ++d)
    for (int e = 0; e < 5; ++e)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) Hb[d][e][3 * a + b] = H[(3 * e + b) * 15 + 3 * d + a];
  for (int d = 0; d < 5; ++d)
    for (int q = 0; q < L; ++q) {
      double* hc = &HC[(size_t(d) * L + q) * 9];
      for (int i = 0; i < 9; ++i) hc[i] = 0.0;
      for (int e = 0; e < 5; ++e) {
        const double w = c[e][q];
        for (int i = 0; i < 9; ++i) hc[i] += w * Hb[d][e][i];
      }
    }
  // each entry of Ke's row p read and written once, its terms added in the order of d as before
  // (the same sums, bit for bit): a fifth of the memory traffic of one pass per d
  for (int p = 0; p < L; ++p) {
    const double* h[5];
    double w[5];
    int n = 0;
    for (int d = 0; d < 5; ++d)
      if (c[d][p] != 0.0) {
        w[n] = c[d][p];
        h[n++] = &HC[size_t(d) * L * 9];
      }
    double* ke = &Ke[size_t(p) * L * 9];
    const int i0 = 9 * p, i1 = 9 * L;
    switch (n) {
      case 5:
        for (int i = i0; i < i1; ++i) {
          double t = ke[i] + w[0] * h[0][i];
          t = t + w[1] * h[1][i];
          t = t + w[2] * h[2][i];
          t = t + w[3] * h[3][i];
          ke[i] = t + w[4] * h[4][i];
        }
        break;
      case 3:
        for (int i = i0; i < i1; ++i) {
          double t = ke[i] + w[0] * h[0][i];
          t = t + w[1] * h[1][i];
          ke[i] = t + w[2] * h[2][i];
        }
        break;
      default:
        for (int i = i0; i < i1; ++i) {
          double t = ke[i];
          for (int k = 0; k < n; ++k) t = t + w[k] * h[k][i];
          ke[i] = t;
        }
    }
  }
}

/// accumulateElementBody with the element's point count fixed for bicubic (16) and biquadratic
/// (9) elements, else read at run time; each compiled for AVX2 and the baseline. The loops and
/// so the sums' orders are the same in all (bit-identical results).
BSDEFORM_MULTIVERSION
void accumulateElement16(const double (*c)[kMaxPoints * kMaxPoints], const double* H, double* HC, double* Ke) {
  accumulateElementBody<16>(16, c, H, HC, Ke);
}
BSDEFORM_MULTIVERSION
void accumulateElement9(const double (*c)[kMaxPoints * kMaxPoints], const double* H, double* HC, double* Ke) {
  accumulateElementBody<9>(9, c, H, HC, Ke);
}
BSDEFORM_MULTIVERSION
void accumulateElementAny(int L, const double (*c)[kMaxPoints * kMaxPoints], const double* H, double* HC, double* Ke) {
  accumulateElementBody<0>(L, c, H, HC, Ke);
}
void accumulateElement(int L, const double (*c)[kMaxPoints * kMaxPoints], const double* H, double* HC, double* Ke) {
  if (L == 16)
    accumulateElement16(c, H, HC, Ke);
  else if (L == 9)
    accumulateElement9(c, H, HC, Ke);
  else
    accumulateElementAny(L, c, H, HC, Ke);
}

/// Runs fn(law) with the material's law (ShellLaws.h): the kernels are instantiated per law.
template <typename Fn>
void withLaw(const ShellMaterial& m, bool split, Fn&& fn) {
  if (m.law == ShellMaterialLaw::NeoHookean) {
    NeoHookean law(m);
    law.split = split;
    fn(law);
  } else {
    fn(SaintVenantKirchhoff(m));
  }
}

}  // namespace

ShellEnergy::ShellEnergy(const SplineSpace& space, const ControlNet& rest, const ShellMaterial& material)
    : m_space(space), m_rest(rest), m_material(material) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
  };
  const ShellMaterial& m = material;
  requireParameter(std::isfinite(m.youngsModulus) && m.youngsModulus > 0.0, "youngsModulus",
                   "must be a finite number > 0 (got " + numberText(m.youngsModulus) + ")");
  requireParameter(std::isfinite(m.poissonRatio) && m.poissonRatio >= 0.0 && m.poissonRatio < 0.5, "poissonRatio",
                   "must lie in [0, 0.5) (got " + numberText(m.poissonRatio) + ")");
  requireParameter(std::isfinite(m.thickness) && m.thickness > 0.0, "thickness",
                   "must be a finite number > 0 (got " + numberText(m.thickness) + ")");
  requireParameter(std::isfinite(m.density) && m.density > 0.0, "density",
                   "must be a finite number > 0 (got " + numberText(m.density) + ")");
  requireParameter(m.law == ShellMaterialLaw::SaintVenantKirchhoff || m.law == ShellMaterialLaw::NeoHookean,
                   "material",
                   "must be SAINT_VENANT_KIRCHHOFF or NEO_HOOKEAN (got " + std::to_string(int(m.law)) + ")");
  require(rest.rows() == space.netSize(), "ShellEnergy: the rest net does not fit the spline space");
  m_bending = space.degreeU() >= 2 && space.degreeV() >= 2;
  m_qu = space.degreeU() + 1;
  m_qv = space.degreeV() + 1;
  auto table = [](const BSplineBasis1D& basis, int points, std::vector<double>& t) {
    const QuadratureRule& rule = gaussLegendre(points);
    const int L = basis.degree() + 1;
    t.assign(size_t(points * 3 * L), 0.0);
    for (int q = 0; q < points; ++q) {
      LocalBasis lb;
      basis.evaluateInSpan(0, rule.nodes[size_t(q)] * basis.spacing(), std::min(2, basis.degree()), lb);
      for (int d = 0; d <= std::min(2, basis.degree()); ++d)
        for (int a = 0; a < L; ++a) t[size_t((q * 3 + d) * L + a)] = lb.d[size_t(d)][size_t(a)];
    }
  };
  table(space.basisU(), m_qu, m_tu);
  table(space.basisV(), m_qv, m_tv);
  const QuadratureRule& ru = gaussLegendre(m_qu);
  const QuadratureRule& rv = gaussLegendre(m_qv);
  const int S1 = space.basisU().numSpans(), S2 = space.basisV().numSpans();
  const double h1 = space.basisU().spacing(), h2 = space.basisV().spacing();
  m_points.resize(size_t(S1) * S2 * m_qu * m_qv);
  double area = 0.0;
  for (int e1 = 0; e1 < S1; ++e1)
    for (int e2 = 0; e2 < S2; ++e2)
      for (int q1 = 0; q1 < m_qu; ++q1)
        for (int q2 = 0; q2 < m_qv; ++q2) {
          const double u = (e1 + ru.nodes[size_t(q1)]) * h1, v = (e2 + rv.nodes[size_t(q2)]) * h2;
          const SurfacePoint p = space.evaluate(rest, u, v, 2);
          const Eigen::Vector3d a3 = p.du.cross(p.dv);
          const double J = a3.norm();
          const double scale = p.du.squaredNorm() + p.dv.squaredNorm();
          if (!(J > 1e-10 * scale) || !std::isfinite(J)) {
            std::ostringstream os;
            os << "the rest surface is degenerate at (u, v) = (" << numberText(u) << ", " << numberText(v)
               << "): S_u x S_v vanishes there (a pole?), and a shell needs a regular rest surface";
            throw std::invalid_argument(os.str());
          }
          const Eigen::Vector3d n = a3 / J;
          RestPoint& r = m_points[((size_t(e1) * S2 + e2) * m_qu + q1) * m_qv + q2];
          for (int c = 0; c < 3; ++c) {
            r.T[c] = p.du[c];
            r.T[3 + c] = p.dv[c];
          }
          r.A[0] = p.du.dot(p.du);
          r.A[1] = p.du.dot(p.dv);
          r.A[2] = p.dv.dot(p.dv);
          const double det = r.A[0] * r.A[2] - r.A[1] * r.A[1];
          r.Ac[0] = r.A[2] / det;
          r.Ac[1] = -r.A[1] / det;
          r.Ac[2] = r.A[0] / det;
          r.B[0] = p.duu.dot(n);
          r.B[1] = p.duv.dot(n);
          r.B[2] = p.dvv.dot(n);
          r.wJ = ru.weights[size_t(q1)] * rv.weights[size_t(q2)] * h1 * h2 * J;
          area += r.wJ;
        }
  m_restArea = area;
}

double ShellEnergy::restAreaElement(double u, double v) const {
  const SurfacePoint p = m_space.evaluate(m_rest, u, v, 1);
  return p.du.cross(p.dv).norm();
}

// Rows of the net are split into blocks of knot spans in u; blocks of one parity touch disjoint
// net rows (a block spans at least n1 + 1 spans), so each parity runs its blocks in parallel and
// every net row receives its sums in the same order for any thread count.
template <typename Fn>
void ShellEnergy::forEachBlock(Fn&& fn) const {
  const int S1 = m_space.basisU().numSpans();
  const int size = blockSize(), blocks = numBlocks();
  for (int parity = 0; parity < 2; ++parity) {
    const int parts = (blocks - parity + 1) / 2;
    if (parts <= 0) continue;
    runParts(parts, [&](int p) {
      const int b = 2 * p + parity;
      fn(b, b * size, std::min(S1, (b + 1) * size));
    });
  }
}

ShellEnergies ShellEnergy::energy(const ControlNet& net) const {
  const int S2 = m_space.basisV().numSpans();
  const Tables tb{m_space.degreeU() + 1, m_space.degreeV() + 1, m_qu, m_qv, m_space.netCols(), m_tu.data(), m_tv.data()};
  std::vector<ShellEnergies> partial(static_cast<size_t>(numBlocks()));
  const double* X = net.data();
  withLaw(m_material, true, [&](const auto& law) {
    forEachBlock([&](int b, int s0, int s1) {
      ShellEnergies sum;
      for (int e1 = s0; e1 < s1; ++e1)
        for (int e2 = 0; e2 < S2; ++e2) {
          double em, eb;
          anyElementPass<double>(
              tb, e1, e2, &m_points[(size_t(e1) * S2 + e2) * m_qu * m_qv], law, m_bending, false,
              [X](Eigen::Index r, int c) { return X[3 * r + c]; }, [](Eigen::Index, int, double) {}, em, eb);
          sum.membrane += em;
          sum.bending += eb;
        }
      partial[size_t(b)] = sum;
    });
  });
  ShellEnergies total;
  for (const ShellEnergies& p : partial) {
    total.membrane += p.membrane;
    total.bending += p.bending;
  }
  return total;
}

void ShellEnergy::gradient(const ControlNet& net, ControlNet& grad, double* energy) const {
  const int S2 = m_space.basisV().numSpans();
  const Tables tb{m_space.degreeU() + 1, m_space.degreeV() + 1, m_qu, m_qv, m_space.netCols(), m_tu.data(), m_tv.data()};
  std::vector<double> partial(size_t(numBlocks()), 0.0);  // per block (forEachBlock)
  withLaw(m_material, false, [&](const auto& law) {
    grad.setZero(net.rows(), 3);
    const double* X = net.data();
    double* G = grad.data();
    forEachBlock([&](int b, int s0, int s1) {
      double sum = 0.0;
      for (int e1 = s0; e1 < s1; ++e1)
        for (int e2 = 0; e2 < S2; ++e2) {
          double em, eb;
          anyElementPass<double>(
              tb, e1, e2, &m_points[(size_t(e1) * S2 + e2) * m_qu * m_qv], law, m_bending, true,
              [X](Eigen::Index r, int c) { return X[3 * r + c]; },
              [G](Eigen::Index r, int c, double s) { G[3 * r + c] += s; }, em, eb);
          sum += em + eb;
        }
      partial[size_t(b)] = sum;
    });
  });
  if (energy) {
    *energy = 0.0;
    for (double p : partial) *energy += p;
  }
}

void ShellEnergy::hessianProduct(const ControlNet& net, const ControlNet& dir, ControlNet& out) const {
  const int S2 = m_space.basisV().numSpans();
  const Tables tb{m_space.degreeU() + 1, m_space.degreeV() + 1, m_qu, m_qv, m_space.netCols(), m_tu.data(), m_tv.data()};
  withLaw(m_material, false, [&](const auto& law) {
    out.setZero(net.rows(), 3);
    const double* X = net.data();
    const double* D = dir.data();
    double* O = out.data();
    forEachBlock([&](int, int s0, int s1) {
      for (int e1 = s0; e1 < s1; ++e1)
        for (int e2 = 0; e2 < S2; ++e2) {
          Dual em, eb;
          anyElementPass<Dual>(
              tb, e1, e2, &m_points[(size_t(e1) * S2 + e2) * m_qu * m_qv], law, m_bending, true,
              [X, D](Eigen::Index r, int c) { return Dual(X[3 * r + c], D[3 * r + c]); },
              [O](Eigen::Index r, int c, Dual s) { O[3 * r + c] += s.b; }, em, eb);
        }
    });
  });
}

bool ShellEnergy::elementHessians(const ControlNet& net, HessianMode mode, bool serial,
                                  const std::function<void(int, int, const double*)>& sink) const {
  std::atomic<bool> anyProjected{false};  // whether any Gauss point's was (the same for any order)
  const int S1 = m_space.basisU().numSpans(), S2 = m_space.basisV().numSpans();
  const int L1 = m_space.degreeU() + 1, L2 = m_space.degreeV() + 1, L = L1 * L2, cols = m_space.netCols();
  const Tables tb{L1, L2, m_qu, m_qv, cols, m_tu.data(), m_tv.data()};
  const std::vector<PointCoefficients> coefficients = elementCoefficients(tb);
  withLaw(m_material, false, [&](const auto& law) {
    const bool project = mode != HessianMode::Exact;
    auto elements = [&](int s0, int s1) {
      // K_pq = Σ_d c[d][p] (Σ_e c[e][q] H_de) in 3 x 3 blocks, the upper blocks (q >= p) only,
      // mirrored at the end
      std::vector<double> Ke(size_t(L) * L * 9), HC(size_t(5) * L * 9);
      alignas(32) double H[225];
      for (int e1 = s0; e1 < s1; ++e1)
        for (int e2 = 0; e2 < S2; ++e2) {
          std::fill(Ke.begin(), Ke.end(), 0.0);
          const RestPoint* rest = &m_points[(size_t(e1) * S2 + e2) * m_qu * m_qv];
          double X[kMaxPoints * kMaxPoints][3];
          for (int p = 0; p < L; ++p) {
            const Eigen::Index r = Eigen::Index(e1 + p / L2) * cols + e2 + p % L2;
            for (int cc = 0; cc < 3; ++cc) X[p][cc] = net(r, cc);
          }
          for (int q1 = 0; q1 < m_qu; ++q1)
            for (int q2 = 0; q2 < m_qv; ++q2) {
              const double(*c)[kMaxPoints * kMaxPoints] = coefficients[size_t(q1 * m_qv + q2)].c;
              double y[15] = {};
              for (int p = 0; p < L; ++p)
                for (int m = 0; m < 5; ++m)
                  for (int cc = 0; cc < 3; ++cc) y[3 * m + cc] += c[m][p] * X[p][cc];
              if (densityHessian(y, rest[q1 * m_qv + q2], law, m_bending, project, H))
                anyProjected.store(true, std::memory_order_relaxed);
              accumulateElement(L, c, H, HC.data(), Ke.data());
            }
          for (int p = 0; p < L; ++p)
            for (int q = 0; q < p; ++q)
              for (int a = 0; a < 3; ++a)
                for (int b = 0; b < 3; ++b)
                  Ke[(size_t(p) * L + q) * 9 + 3 * a + b] = Ke[(size_t(q) * L + p) * 9 + 3 * b + a];
          sink(e1, e2, Ke.data());
        }
    };
    if (serial)
      elements(0, S1);
    else
      forEachBlock([&](int, int s0, int s1) { elements(s0, s1); });
  });
  return anyProjected.load();
}

void ShellEnergy::hessian(const ControlNet& net, bool project, std::vector<Eigen::Triplet<double>>& out) const {
  const int S1 = m_space.basisU().numSpans(), S2 = m_space.basisV().numSpans();
  const int L2 = m_space.degreeV() + 1, L = (m_space.degreeU() + 1) * L2, cols = m_space.netCols();
  out.clear();
  out.reserve(size_t(S1) * S2 * size_t(9 * L * L));
  elementHessians(net, project ? HessianMode::Projected : HessianMode::Exact, true,
                  [&](int e1, int e2, const double* Ke) {
                    for (int p = 0; p < L; ++p) {
                      const Eigen::Index rp = Eigen::Index(e1 + p / L2) * cols + e2 + p % L2;
                      for (int q = 0; q < L; ++q) {
                        const Eigen::Index rq = Eigen::Index(e1 + q / L2) * cols + e2 + q % L2;
                        const double* ke = &Ke[(size_t(p) * L + q) * 9];
                        for (int a = 0; a < 3; ++a)
                          for (int b = 0; b < 3; ++b) out.emplace_back(int(3 * rp + a), int(3 * rq + b), ke[3 * a + b]);
                      }
                    }
                  });
}

Eigen::VectorXd ShellEnergy::lumpedMass() const {
  const int S1 = m_space.basisU().numSpans(), S2 = m_space.basisV().numSpans();
  const int L1 = m_space.degreeU() + 1, L2 = m_space.degreeV() + 1, cols = m_space.netCols();
  const Tables tb{L1, L2, m_qu, m_qv, cols, m_tu.data(), m_tv.data()};
  const double rhoT = m_material.density * m_material.thickness;
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(m_space.netSize());
  for (int e1 = 0; e1 < S1; ++e1)
    for (int e2 = 0; e2 < S2; ++e2)
      for (int q1 = 0; q1 < m_qu; ++q1)
        for (int q2 = 0; q2 < m_qv; ++q2) {
          const double wJ = m_points[((size_t(e1) * S2 + e2) * m_qu + q1) * m_qv + q2].wJ;
          for (int a = 0; a < L1; ++a)
            for (int b = 0; b < L2; ++b)
              mass[Eigen::Index(e1 + a) * cols + e2 + b] += rhoT * wJ * tb.u(q1, 0, a) * tb.v(q2, 0, b);
        }
  return mass;
}

double ShellEnergy::eigenvalueBound(const ControlNet& net, const Eigen::VectorXd& mass) const {
  const int S2 = m_space.basisV().numSpans();
  const int L1 = m_space.degreeU() + 1, L2 = m_space.degreeV() + 1, L = L1 * L2, cols = m_space.netCols();
  const Tables tb{L1, L2, m_qu, m_qv, cols, m_tu.data(), m_tv.data()};
  Eigen::VectorXd rows = Eigen::VectorXd::Zero(m_space.netSize());
  const std::vector<PointCoefficients> coefficients = elementCoefficients(tb);
  withLaw(m_material, false, [&](const auto& law) {
    forEachBlock([&](int, int s0, int s1) {
      for (int e1 = s0; e1 < s1; ++e1)
        for (int e2 = 0; e2 < S2; ++e2) {
          const RestPoint* rest = &m_points[(size_t(e1) * S2 + e2) * m_qu * m_qv];
          for (int q1 = 0; q1 < m_qu; ++q1)
            for (int q2 = 0; q2 < m_qv; ++q2) {
              const double(*c)[kMaxPoints * kMaxPoints] = coefficients[size_t(q1 * m_qv + q2)].c;
              double y[15] = {};
              for (int p = 0; p < L; ++p) {
                const Eigen::Index r = Eigen::Index(e1 + p / L2) * cols + e2 + p % L2;
                for (int m = 0; m < 5; ++m)
                  for (int cc = 0; cc < 3; ++cc) y[3 * m + cc] += c[m][p] * net(r, cc);
              }
              Eigen::Matrix<double, 15, 15> H;
              densityHessian(y, rest[q1 * m_qv + q2], law, m_bending, false, H.data());
              double s[5] = {};
              for (int m = 0; m < 5; ++m)
                for (int p = 0; p < L; ++p) s[m] += std::abs(c[m][p]);
              double rd[5] = {};
              for (int d = 0; d < 5; ++d)
                for (int e = 0; e < 5; ++e) {
                  const double block = H.block<3, 3>(3 * d, 3 * e).cwiseAbs().rowwise().sum().maxCoeff();
                  rd[d] += s[e] * block;
                }
              for (int p = 0; p < L; ++p) {
                double sum = 0.0;
                for (int d = 0; d < 5; ++d) sum += std::abs(c[d][p]) * rd[d];
                rows[Eigen::Index(e1 + p / L2) * cols + e2 + p % L2] += sum;
              }
            }
        }
    });
  });
  double bound = 0.0;
  for (Eigen::Index p = 0; p < rows.size(); ++p)
    if (mass[p] > 0.0) bound = std::max(bound, rows[p] / mass[p]);
  return bound;
}

}  // namespace bsdeform
