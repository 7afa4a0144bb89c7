// SPDX-License-Identifier: MIT
// The collision proxy: its vertices are the surface's points at their parameters, its loads are
// the transpose of its positions (virtual work), and its deviation bound holds and is not loose.
#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <random>

#include "bsdeform/contact/CollisionProxy.h"

using namespace bsdeform;

namespace {
// A doubly curved net: a cap z = 0.3 (x² + y²) with a ripple, on the Greville abscissae.
ControlNet cap(const SplineSpace& s, double ripple) {
  ControlNet net = ControlNet::Zero(s.netSize(), 3);
  for (int k1 = -s.degreeU(); k1 < s.numU() + s.degreeU(); ++k1)
    for (int k2 = -s.degreeV(); k2 < s.numV() + s.degreeV(); ++k2) {
      const double x = s.grevilleU(k1), y = s.grevilleV(k2);
      net.row(s.netIndex(k1, k2)) << x, y, 0.3 * (x * x + y * y) + ripple * std::sin(9.0 * x) * std::cos(7.0 * y);
    }
  return net;
}
}  // namespace

TEST_CASE("CollisionProxy: vertices are surface points and loads are the transpose of positions", "[core][contact]") {
  for (Boundary side : {Boundary::Clamped, Boundary::Free, Boundary::SimplySupported}) {
    INFO("side " << boundaryName(side));
    Boundaries b;
    b.uMin = b.vMax = side;
    const SplineSpace s(3, 2, 5, 4, b);
    ControlNet net = cap(s, 0.05);
    s.completeNet(net, &net);
    const CollisionProxy proxy(s, 3);
    Eigen::MatrixX3d V;
    proxy.positions(net, V);
    CHECK(V.rows() == (3 * 8 + 1) * (3 * 6 + 1));
    for (Eigen::Index k = 0; k < V.rows(); ++k) {
      const Eigen::Vector2d uv = proxy.parameters(k);
      CHECK((V.row(k).transpose() - s.evaluate(net, uv.x(), uv.y(), 0).position).norm() < 1e-13);
    }
    // every triangle's vertices depend on the control points of its element only
    for (Eigen::Index t = 0; t < proxy.triangles().rows(); ++t) {
      const auto [e1, e2] = proxy.triangleElement(t);
      for (int c = 0; c < 3; ++c)
        for (const auto& w : proxy.netWeights(proxy.triangles()(t, c))) {
          const int i = int(w.index / s.netCols()), j = int(w.index % s.netCols());
          CHECK((i >= e1 && i <= e1 + 3 && j >= e2 && j <= e2 + 2));
        }
    }
    // Σ_k f_k · δV_k = load · δP for a displacement δP of the moving points
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> X(-1.0, 1.0);
    Eigen::MatrixX3d f(V.rows(), 3);
    for (Eigen::Index i = 0; i < f.size(); ++i) f.data()[i] = X(rng);
    ControlNet dP(s.numMoving(), 3);
    for (Eigen::Index i = 0; i < dP.size(); ++i) dP.data()[i] = X(rng);
    ControlNet moved = net;
    s.scatterMoving(s.gatherMoving(net) + dP, moved);
    s.completeNet(moved, &net);
    Eigen::MatrixX3d V2;
    proxy.positions(moved, V2);
    ControlNet load = ControlNet::Zero(s.numMoving(), 3);
    proxy.addVertexForces(f, load);
    const double work = (f.array() * (V2 - V).array()).sum();
    CHECK(std::abs(work - (load.array() * dP.array()).sum()) < 1e-10 * (1.0 + std::abs(work)));
    // in a world frame: the fused pass equals the positions mapped afterwards, bit for bit
    // (identity, and a rotation with a scale and an offset)
    const Eigen::Matrix3d A = 1.7 * Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
    const Eigen::Vector3d shift(0.3, -1.25, 2.0);
    for (int frame = 0; frame < 2; ++frame) {
      const Eigen::Matrix3d L = frame == 0 ? Eigen::Matrix3d::Identity() : A;
      const Eigen::Vector3d o = frame == 0 ? Eigen::Vector3d::Zero() : shift;
      Eigen::MatrixX3d W;
      proxy.positions(moved, L, o, W);
      const Eigen::MatrixX3d expected = (V2 * L.transpose()).rowwise() + o.transpose();
      REQUIRE(W.rows() == expected.rows());
      CHECK(std::memcmp(W.data(), expected.data(), sizeof(double) * size_t(W.size())) == 0);
      CHECK((W - expected).cwiseAbs().maxCoeff() == 0.0);
    }
  }
}

TEST_CASE("CollisionProxy: periodic directions wrap without a seam", "[core][contact]") {
  Boundaries b;
  b.uMin = b.uMax = Boundary::Periodic;
  const SplineSpace s(3, 3, 8, 3, b);
  const CollisionProxy proxy(s, 2);
  CHECK(proxy.numVertices() == (2 * 11) * (2 * 6 + 1));
  CHECK(proxy.triangles().rows() == 2 * (2 * 11) * (2 * 6));
  // a closed strip: every edge but those of the two rims is in two triangles
  CHECK(proxy.edges().rows() == 3 * 22 * 12 + 22);
}

TEST_CASE("CollisionProxy: the deviation bound holds and is within 8 times the sampled deviation", "[core][contact]") {
  for (int r : {1, 2, 4}) {
    for (int degree : {2, 3}) {
      INFO("samples " << r << ", degree " << degree);
      const SplineSpace s(degree, degree, 6, 6);
      const ControlNet net = cap(s, 0.02);
      const CollisionProxy proxy(s, r);
      Eigen::MatrixX3d V;
      proxy.positions(net, V);
      double worst = 0.0;
      const int n = 12;
      for (Eigen::Index t = 0; t < proxy.triangles().rows(); ++t)
        for (int a = 0; a <= n; ++a)
          for (int c = 0; a + c <= n; ++c) {
            const double l1 = double(a) / n, l2 = double(c) / n, l0 = 1.0 - l1 - l2;
            const auto tri = proxy.triangles().row(t);
            const Eigen::Vector2d uv =
                l0 * proxy.parameters(tri(0)) + l1 * proxy.parameters(tri(1)) + l2 * proxy.parameters(tri(2));
            const Eigen::Vector3d flat = (l0 * V.row(tri(0)) + l1 * V.row(tri(1)) + l2 * V.row(tri(2))).transpose();
            worst = std::max(worst, (s.evaluate(net, uv.x(), uv.y(), 0).position - flat).norm());
          }
      const double bound = proxy.deviationBound(net);
      CHECK(worst <= bound);
      CHECK(bound <= 8.0 * worst);
    }
  }
}
