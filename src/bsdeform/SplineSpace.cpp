// SPDX-License-Identifier: MIT
#include "bsdeform/SplineSpace.h"

#include <stdexcept>
#include <string>

namespace bsdeform {

Eigen::Vector3d SurfacePoint::normal() const {
  Eigen::Vector3d n = du.cross(dv);
  const double len = n.norm();
  return len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

namespace {
BSplineBasis1D makeBasis(int degree, int numFree, const char* degreeName, const char* countName) {
  if (degree < 1 || degree > kMaxDegree)
    throw std::invalid_argument(std::string(degreeName) + " must be between 1 and " + std::to_string(kMaxDegree) +
                                ", got " + std::to_string(degree));
  if (numFree < 1)
    throw std::invalid_argument(std::string(countName) + " (free control points) must be at least 1, got " +
                                std::to_string(numFree));
  constexpr int kMaxPerSide = 1 << 16;
  if (numFree > kMaxPerSide)
    throw std::invalid_argument(std::string(countName) + " must be at most " + std::to_string(kMaxPerSide) +
                                ", got " + std::to_string(numFree));
  return BSplineBasis1D(degree, numFree);
}
}  // namespace

SplineSpace::SplineSpace(int degreeU, int degreeV, int numFreeU, int numFreeV)
    : m_u(makeBasis(degreeU, numFreeU, "degreeU", "numU")), m_v(makeBasis(degreeV, numFreeV, "degreeV", "numV")) {}

double SplineSpace::grevilleU(int k1) const { return (k1 + 0.5 * (degreeU() + 1)) * m_u.spacing(); }
double SplineSpace::grevilleV(int k2) const { return (k2 + 0.5 * (degreeV() + 1)) * m_v.spacing(); }

ControlNet SplineSpace::grevillePlane() const {
  ControlNet net(netSize(), 3);
  for (int k1 = -degreeU(); k1 < numFreeU() + degreeU(); ++k1)
    for (int k2 = -degreeV(); k2 < numFreeV() + degreeV(); ++k2)
      net.row(netIndex(k1, k2)) << grevilleU(k1), grevilleV(k2), 0.0;
  return net;
}

ControlNet SplineSpace::gatherFree(const ControlNet& net) const {
  ControlNet f(numFree(), 3);
  for (Eigen::Index i = 0; i < numFree(); ++i) f.row(i) = net.row(freeToNet(i));
  return f;
}

void SplineSpace::scatterFree(const ControlNet& freePoints, ControlNet& net) const {
  for (Eigen::Index i = 0; i < numFree(); ++i) net.row(freeToNet(i)) = freePoints.row(i);
}

SurfacePoint SplineSpace::evaluate(const ControlNet& net, double u, double v, int order) const {
  LocalBasis bu, bv;
  m_u.evaluate(u, order, bu);
  m_v.evaluate(v, order, bv);
  return evaluate(net, bu, bv, order);
}

SurfacePoint SplineSpace::evaluate(const ControlNet& net, const LocalBasis& bu, const LocalBasis& bv, int order) const {
  SurfacePoint p;
  const int nu = degreeU(), nv = degreeV();
  for (int a = 0; a < bu.count; ++a) {
    Eigen::Vector3d c0 = Eigen::Vector3d::Zero(), c1 = Eigen::Vector3d::Zero(), c2 = Eigen::Vector3d::Zero();
    const Eigen::Index rowBase = Eigen::Index(bu.first + a + nu) * netCols() + (bv.first + nv);
    for (int b = 0; b < bv.count; ++b) {
      const Eigen::Vector3d P = net.row(rowBase + b).transpose();
      c0 += bv.d[0][b] * P;
      if (order >= 1) c1 += bv.d[1][b] * P;
      if (order >= 2) c2 += bv.d[2][b] * P;
    }
    p.position += bu.d[0][a] * c0;
    if (order >= 1) {
      p.du += bu.d[1][a] * c0;
      p.dv += bu.d[0][a] * c1;
    }
    if (order >= 2) {
      p.duu += bu.d[2][a] * c0;
      p.duv += bu.d[1][a] * c1;
      p.dvv += bu.d[0][a] * c2;
    }
  }
  return p;
}

}  // namespace bsdeform
