// SPDX-License-Identifier: MIT
#pragma once
/// @file ForceFieldCheck.h
/// One finite-difference fixture for every force law (SOFA's ForceField_test): given a law's
/// load L(P) on the moving control points P at a state, and where it has them its energy E(P)
/// and its Jacobian product (dL/dP) d, ForceFieldCheck::run() checks along random directions d
///  - L = -dE/dP:        dE(P + t d)/dt at 0 against -L . d (conservative laws),
///  - the Jacobian:      (L(P + t d))'(0) against the law's (dL/dP) d (laws that provide it),
///  - symmetry:          e . (dL/dP) d = d . (dL/dP) e (conservative laws: dL/dP = -Hessian),
/// every derivative by fourth-order central differences. A law without an energy (pressure,
/// drag, damping) gets the Jacobian check only. forForce() adapts a Force (Force.h); an
/// ElasticEnergy gives L = -gradient, E = energy and (dL/dP) d = -H d directly.
///
/// The helpers below it build states and reference Jacobians of laws integrated over the
/// surface: a deformed net, the tensor Gauss rule DistributedForce uses, the moving B-splines at
/// a point, and \f$J_{mn} = \sum_q w_q B_m(q)\, \partial f(q)/\partial P_n\f$.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "bsdeform/spline/BSpline.h"
#include "bsdeform/forces/Force.h"
#include "bsdeform/spline/GaussLegendre.h"
#include "bsdeform/spline/SplineSpace.h"

namespace bsdeform::test {

/// Fourth-order central difference of f at 0 with step h.
template <typename F>
double derivative(F&& f, double h) {
  return (4 * (f(h) - f(-h)) / (2 * h) - (f(2 * h) - f(-2 * h)) / (4 * h)) / 3;
}

inline double dot(const ControlNet& a, const ControlNet& b) { return (a.array() * b.array()).sum(); }

struct ForceFieldCheck {
  std::string name;
  /// The state: the moving control points (numMoving x 3).
  ControlNet P;
  /// The full net of moving points Q (periodic copies, derived layers).
  std::function<ControlNet(const ControlNet& Q)> netOf;
  /// The load on the moving points at a full net (numMoving x 3).
  std::function<ControlNet(const ControlNet& net)> load;
  /// The energy at a full net, with L = -dE/dP; empty for a law without one.
  std::function<double(const ControlNet& net)> energy;
  /// (dL/dP) d at the state for a displacement d of the moving points; empty: none.
  std::function<ControlNet(const ControlNet& d)> jacobianProduct;
  double step = 1e-6;               ///< of the central differences, per unit of d (entries in [-1, 1])
  double tolerance = 1e-6;          ///< relative to the size of the compared quantity
  double absoluteTolerance = 1e-12; ///< for quantities that vanish
  int directions = 3;
  unsigned seed = 1;

  ControlNet loadAt(const ControlNet& Q) const { return load(netOf(Q)); }

  /// The finite-difference directional derivative of the load, (L(P + t d))'(0).
  ControlNet loadDerivative(const ControlNet& d) const {
    const double h = step;
    const ControlNet l1 = loadAt(P + h * d) - loadAt(P - h * d), l2 = loadAt(P + 2 * h * d) - loadAt(P - 2 * h * d);
    return (4 * l1 / (2 * h) - l2 / (4 * h)) / 3;  // the same fourth-order difference as derivative()
  }

  /// The whole Jacobian dL/dP by finite differences, J(3m+i, 3n+j) = dL_{m,i} / dP_{n,j}.
  Eigen::MatrixXd jacobian() const {
    const Eigen::Index n = P.size();
    Eigen::MatrixXd J(n, n);
    for (Eigen::Index c = 0; c < n; ++c) {
      ControlNet d = ControlNet::Zero(P.rows(), 3);
      d(c / 3, c % 3) = 1.0;
      const ControlNet col = loadDerivative(d);
      for (Eigen::Index r = 0; r < n; ++r) J(r, c) = col(r / 3, r % 3);
    }
    return J;
  }

  /// The checks above; Catch2 CHECKs, so every failing direction is reported.
  void run() const {
    INFO(name);
    REQUIRE((energy || jacobianProduct));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> X(-1.0, 1.0);
    auto random = [&] {
      ControlNet d(P.rows(), 3);
      for (Eigen::Index i = 0; i < d.size(); ++i) d.data()[i] = X(rng);
      return d;
    };
    const ControlNet L = loadAt(P);
    for (int k = 0; k < directions; ++k) {
      INFO("direction " << k);
      const ControlNet d = random(), e = random();
      if (energy) {
        const double dE = derivative([&](double t) { return energy(netOf(P + t * d)); }, step);
        CHECK(std::abs(dE + dot(L, d)) <= tolerance * L.norm() * d.norm() + absoluteTolerance);
      }
      const ControlNet Jd = jacobianProduct ? jacobianProduct(d) : loadDerivative(d);
      if (jacobianProduct) {
        const ControlNet fd = loadDerivative(d);
        CHECK((fd - Jd).norm() <= tolerance * Jd.norm() + absoluteTolerance);
      }
      if (energy) {
        const ControlNet Je = jacobianProduct ? jacobianProduct(e) : loadDerivative(e);
        CHECK(std::abs(dot(e, Jd) - dot(d, Je)) <= tolerance * Jd.norm() * e.norm() + absoluteTolerance);
      }
    }
  }
};

/// A Force at `net` (a full net): its load with `previous` (the net a step `dt` before, for
/// velocities; the state itself when null) held fixed while the state moves. The energy and
/// Jacobian product are the caller's to set.
inline ForceFieldCheck forForce(std::string name, const Force& force, const SplineSpace& space, const ControlNet& net,
                                const ControlNet* previous = nullptr, double dt = 0.1, const ControlNet* rest = nullptr) {
  ForceFieldCheck c;
  c.name = std::move(name);
  c.P = space.gatherMoving(net);
  c.netOf = [&space, net](const ControlNet& Q) {
    ControlNet out = net;
    space.scatterMoving(Q, out);
    return out;
  };
  const ControlNet prev = previous ? *previous : net;
  c.load = [&force, &space, prev, dt, rest](const ControlNet& current) {
    ControlNet load = ControlNet::Zero(space.numMoving(), 3);
    LoadContext ctx{space, current, prev, dt, 0.0};
    ctx.rest = rest;
    force.addLoad(ctx, load);
    return load;
  };
  return c;
}

/// The force's own derivatives (Force::addJacobian(), Force::potential()) as the check's
/// Jacobian product and energy, with `previous` fixed: the velocity (current - previous) / dt
/// moves with the state, so the Jacobian asked for is -dL/dx - (1/dt) dL/dv. The blocks between
/// net points are folded onto the moving points (periodic copies, derived layers) here, in a
/// dense matrix: independent of the solver's TangentMatrix.
inline void useOwnDerivatives(ForceFieldCheck& c, const Force& force, const SplineSpace& space, const ControlNet& net,
                              const ControlNet* previous = nullptr, double dt = 0.1, const ControlNet* rest = nullptr) {
  const ControlNet prev = previous ? *previous : net;
  const Eigen::Index N = space.numMoving();
  struct Dense final : JacobianSink {
    const SplineSpace& s;
    Eigen::MatrixXd K;
    explicit Dense(const SplineSpace& sp) : s(sp), K(Eigen::MatrixXd::Zero(3 * sp.numMoving(), 3 * sp.numMoving())) {}
    void add(Eigen::Index p, Eigen::Index q, const Eigen::Matrix3d& B) override {
      const int cols = s.netCols(), w = s.movingV().count;
      auto fold = [&](Eigen::Index r, auto&& fn) {
        for (const LayerWeight& wu : s.foldU(int(r / cols)))
          for (const LayerWeight& wv : s.foldV(int(r % cols)))
            fn(Eigen::Index(wu.layer - s.movingU().first) * w + (wv.layer - s.movingV().first), wu.weight * wv.weight);
      };
      fold(p, [&](Eigen::Index f, double wf) {
        fold(q, [&](Eigen::Index g, double wg) { K.block<3, 3>(3 * f, 3 * g) += wf * wg * B; });
      });
    }
  } sink(space);
  LoadContext ctx{space, net, prev, dt, 0.0};
  ctx.rest = rest;
  force.addJacobian(ctx, 1.0 / dt, sink);
  const Eigen::MatrixXd J = -sink.K;  // dL/dP
  c.jacobianProduct = [J, N](const ControlNet& d) {
    ControlNet dr = d;  // row-major per point: index 3 m + i
    Eigen::VectorXd x(3 * N);
    for (Eigen::Index m = 0; m < N; ++m)
      for (int i = 0; i < 3; ++i) x[3 * m + i] = dr(m, i);
    const Eigen::VectorXd y = J * x;
    ControlNet out(N, 3);
    for (Eigen::Index m = 0; m < N; ++m)
      for (int i = 0; i < 3; ++i) out(m, i) = y[3 * m + i];
    return out;
  };
  double probe = 0.0;
  if (force.potential(ctx, probe))
    c.energy = [&force, &space, prev, dt, rest](const ControlNet& current) {
      LoadContext cx{space, current, prev, dt, 0.0};
      cx.rest = rest;
      double value = 0.0;
      force.potential(cx, value);
      return value;
    };
}

// ---------------------------------------------------------------------------------------------
// States and reference Jacobians of surface-integrated laws

/// The Greville plane (or, periodic, the Greville abscissae of the moving points) with a bump
/// of height `amp` and a small in-plane distortion: a "small deformed net".
inline ControlNet deformedNet(const SplineSpace& s, double amp) {
  constexpr double kPi = 3.14159265358979323846;
  ControlNet net = ControlNet::Zero(s.netSize(), 3);
  for (int k1 = -s.degreeU(); k1 < s.numU() + s.degreeU(); ++k1)
    for (int k2 = -s.degreeV(); k2 < s.numV() + s.degreeV(); ++k2)
      net.row(s.netIndex(k1, k2)) << s.grevilleU(k1), s.grevilleV(k2), 0.0;
  ControlNet P = s.gatherMoving(net);
  for (Eigen::Index f = 0; f < P.rows(); ++f) {
    const double x = P(f, 0), y = P(f, 1);
    P(f, 2) += amp * std::sin(kPi * x) * std::sin(kPi * y) + 0.05 * amp * std::cos(3.0 * x + 2.0 * y);
    P(f, 0) += 0.03 * std::sin(2.0 * y + 0.3);
    P(f, 1) += 0.02 * std::cos(3.0 * x);
  }
  s.scatterMoving(P, net);
  return net;
}

/// A point of a quadrature rule on the parameter square.
struct QPoint {
  double u, v, w;
};

/// Tensor Gauss rule with `pointsU` x `pointsV` nodes on every knot cell of [u0,u1] x [v0,v1]
/// (edges on knots; the whole square by default).
inline std::vector<QPoint> tensorRule(const SplineSpace& s, int pointsU, int pointsV, ParamRect rect = ParamRect()) {
  const QuadratureRule &ru = gaussLegendre(pointsU), &rv = gaussLegendre(pointsV);
  const int su = s.basisU().numSpans(), sv = s.basisV().numSpans();
  std::vector<QPoint> out;
  for (int a = int(std::lround(rect.u0 * su)); a < int(std::lround(rect.u1 * su)); ++a)
    for (size_t p = 0; p < ru.nodes.size(); ++p)
      for (int b = int(std::lround(rect.v0 * sv)); b < int(std::lround(rect.v1 * sv)); ++b)
        for (size_t q = 0; q < rv.nodes.size(); ++q)
          out.push_back({(a + ru.nodes[p]) / su, (b + rv.nodes[q]) / sv, ru.weights[p] / su * rv.weights[q] / sv});
  return out;
}

/// The rule DistributedForce uses for densities that are not constant (n + 1 + 2 points).
inline std::vector<QPoint> classRule(const SplineSpace& s) { return tensorRule(s, s.degreeU() + 3, s.degreeV() + 3); }

/// sum_q w_q phi(S(u_q, v_q)): the energy of a density f = -grad phi per unit parameter area.
inline double surfaceEnergy(const SplineSpace& s, const ControlNet& net, const std::vector<QPoint>& rule,
                            const std::function<double(const Eigen::Vector3d&)>& phi) {
  double E = 0.0;
  for (const QPoint& q : rule) E += q.w * phi(s.evaluate(net, q.u, q.v, 0).position);
  return E;
}

/// B-splines of the moving points at (u, v) and their u, v derivatives (periodic copies summed).
struct MovingBasis {
  Eigen::VectorXd b, bu, bv;
};
inline MovingBasis movingBasis(const SplineSpace& s, double u, double v) {
  LocalBasis lu, lv;
  s.basisU().evaluate(u, 1, lu);
  s.basisV().evaluate(v, 1, lv);
  const Eigen::Index N = s.numMoving();
  MovingBasis out{Eigen::VectorXd::Zero(N), Eigen::VectorXd::Zero(N), Eigen::VectorXd::Zero(N)};
  const int w = s.movingV().count;
  for (int a = 0; a < lu.count; ++a) {
    const int i = s.movingLayerU(lu.first + a + s.degreeU());
    if (i < 0) continue;
    for (int b = 0; b < lv.count; ++b) {
      const int j = s.movingLayerV(lv.first + b + s.degreeV());
      if (j < 0) continue;
      const Eigen::Index m = Eigen::Index(i - s.movingU().first) * w + (j - s.movingV().first);
      out.b[m] += lu.d[0][a] * lv.d[0][b];
      out.bu[m] += lu.d[1][a] * lv.d[0][b];
      out.bv[m] += lu.d[0][a] * lv.d[1][b];
    }
  }
  return out;
}

/// Jacobian of a density law by a quadrature: J_mn = sum_q w_q B_m (df/dP_n), where
/// dfdP(q, basis, n) is the 3x3 derivative of the density at point q w.r.t. moving point n.
inline Eigen::MatrixXd quadratureJacobian(
    const SplineSpace& s, const std::vector<QPoint>& rule,
    const std::function<Eigen::Matrix3d(const QPoint&, const MovingBasis&, Eigen::Index)>& dfdP) {
  const Eigen::Index N = s.numMoving();
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(3 * N, 3 * N);
  for (const QPoint& q : rule) {
    const MovingBasis mb = movingBasis(s, q.u, q.v);
    for (Eigen::Index n = 0; n < N; ++n) {
      if (mb.b[n] == 0.0 && mb.bu[n] == 0.0 && mb.bv[n] == 0.0) continue;
      const Eigen::Matrix3d D = dfdP(q, mb, n);
      for (Eigen::Index m = 0; m < N; ++m)
        if (mb.b[m] != 0.0) J.block<3, 3>(3 * m, 3 * n) += q.w * mb.b[m] * D;
    }
  }
  return J;
}

/// The product of a Jacobian in the order of jacobian() with a displacement of the moving points.
inline std::function<ControlNet(const ControlNet&)> productOf(Eigen::MatrixXd J) {
  return [J = std::move(J)](const ControlNet& d) {
    const Eigen::VectorXd x = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 1>>(d.data(), d.size());
    const Eigen::VectorXd y = J * x;
    ControlNet out(d.rows(), 3);
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 1>>(out.data(), out.size()) = y;
    return out;
  };
}

/// The matrix of a x (the cross product with a).
inline Eigen::Matrix3d crossMatrix(const Eigen::Vector3d& a) {
  Eigen::Matrix3d X;
  X << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return X;
}

}  // namespace bsdeform::test
