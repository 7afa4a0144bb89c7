// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/Reactions.h"

#include <algorithm>
#include <stdexcept>

namespace bsdeform {

namespace {

/// The same degrees and net with every side FREE: every point of the full net is an unknown of
/// it (moving point f is net row f), with the same knots and B-splines (the knot grid never
/// depends on the sides). Loads and the paper's operator built on it are the full net's, unfolded.
SplineSpace unfoldedSpace(const SplineSpace& s) {
  return SplineSpace(s.degreeU(), s.degreeV(), s.numU(), s.numV(),
                     Boundaries{Boundary::Free, Boundary::Free, Boundary::Free, Boundary::Free});
}

/// Layers a side's reaction gathers, counted from its edge: the n whose B-splines do not vanish
/// on the edge, and any further layer it holds (BUILT_IN of degree 1 holds k = 0 too). 0 for a
/// side that holds nothing.
int bandWidth(Boundary side, int degree) {
  if (!sideHoldsSomething(side)) return 0;
  const EdgeLayers e = edgeLayers(side, degree);
  return std::max(degree, e.held + e.derived + e.sources);
}

}  // namespace

bool sideHoldsSomething(Boundary side) {
  return side == Boundary::Clamped || side == Boundary::SimplySupported || side == Boundary::BuiltIn;
}

Eigen::Vector3d SupportReactions::imbalance() const {
  Eigen::Vector3d sum = applied;
  for (const Side& s : sides) sum += s.force;
  for (const Eigen::Vector3d& p : pins) sum += p;
  return sum;
}

ControlNet fullNetEnergyGradient(const Simulation& sim, const ControlNet& net) {
  ControlNet grad;
  if (const ShellEnergy* shell = sim.shell()) {
    shell->gradient(net, grad);
    return grad;
  }
  // the paper's W = a(S - S_ref, S - S_ref) / 2 over [0,1]^2: on the unfolded space every row is
  // the exact (truncated where a B-spline leaves [0,1]) Gram row
  const SplineSpace full = unfoldedSpace(sim.space());
  const StiffnessStencil A(full, sim.parameters().weights);
  if (sim.parameters().reference == ElasticReference::Rest) {
    const ControlNet d = net - sim.rest();
    A.applyMoving(d, grad);
  } else {
    A.applyMoving(net, grad);
  }
  return grad;
}

ControlNet fullNetLoad(const Simulation& sim, const ControlNet& net, double time) {
  const SplineSpace full = unfoldedSpace(sim.space());
  // at rest (previous = current: zero velocity), as Simulation's static solve evaluates them;
  // SHELL densities are per unit rest area (LoadContext::rest)
  LoadContext ctx{full, net, net, sim.subStepSize(), time};
  if (sim.shell()) ctx.rest = &sim.rest();
  ctx.restShape = &sim.rest();
  ControlNet load = ControlNet::Zero(full.numMoving(), 3);
  for (const auto& f : sim.forces()) f->addLoad(ctx, load);
  return load;
}

SupportReactions supportReactions(const Simulation& sim, const ControlNet& net, double loadFactor, double time) {
  const SplineSpace& s = sim.space();
  if (net.rows() != s.netSize())
    throw std::invalid_argument("supportReactions: the net has " + std::to_string(net.rows()) + " points, the model " +
                                std::to_string(s.netSize()));
  const ControlNet L = loadFactor * fullNetLoad(sim, net, time);
  const ControlNet f = fullNetEnergyGradient(sim, net) - L;

  SupportReactions r;
  r.applied = L.colwise().sum().transpose();

  // the supported sides and their bands
  const Boundaries& b = s.boundaries();
  const int rows = s.netRows(), cols = s.netCols();
  struct Band {
    const char* name;
    Boundary side;
    int width;
  };
  Band bands[4] = {{"umin", b.uMin, bandWidth(b.uMin, s.degreeU())},
                   {"umax", b.uMax, bandWidth(b.uMax, s.degreeU())},
                   {"vmin", b.vMin, bandWidth(b.vMin, s.degreeV())},
                   {"vmax", b.vMax, bandWidth(b.vMax, s.degreeV())}};
  // a support per component or a SYMMETRY side (FREE in the space) holds its n outer layers'
  // combinations too: its band is theirs (a symmetry plane's reaction is the force across it)
  for (int k = 0; k < 4; ++k)
    if (sim.parameters().sideSupports[size_t(k)].kind != SideSupport::Kind::None)
      bands[k].width = k < 2 ? s.degreeU() : s.degreeV();
  int sideOf[4];  // index in r.sides, or -1
  for (int k = 0; k < 4; ++k) {
    sideOf[k] = -1;
    if (bands[k].width == 0) continue;
    sideOf[k] = int(r.sides.size());
    r.sides.push_back({bands[k].name, Eigen::Vector3d::Zero()});
  }

  // the pins of every moving point, as Simulation holds them: the (n1+1)(n2+1) B-splines of the
  // knot span containing the pin, through the moving point each stands for
  const std::vector<Eigen::Vector2d>& pins = sim.parameters().pins;
  r.pins.assign(pins.size(), Eigen::Vector3d::Zero());
  std::vector<std::vector<int>> pinsOf(size_t(s.numMoving()));
  for (size_t p = 0; p < pins.size(); ++p) {
    const int su = s.basisU().span(pins[p].x()), sv = s.basisV().span(pins[p].y());
    for (int k1 = su - s.degreeU(); k1 <= su; ++k1)
      for (int k2 = sv - s.degreeV(); k2 <= sv; ++k2) {
        const Eigen::Index m = s.movingIndex(k1, k2);
        if (m < 0) continue;
        std::vector<int>& of = pinsOf[size_t(m)];
        if (std::find(of.begin(), of.end(), int(p)) == of.end()) of.push_back(int(p));
      }
  }

  // the world components each side holds: every one for a side of the space (CLAMPED,
  // SIMPLY_SUPPORTED, BUILT_IN), the chosen ones for a support per component, the plane's
  // normal for a SYMMETRY side (its plane carries no force along itself)
  unsigned sideHolds[4] = {7u, 7u, 7u, 7u};
  for (int k = 0; k < 4; ++k) {
    const SideSupport& support = sim.parameters().sideSupports[size_t(k)];
    if (support.kind == SideSupport::Kind::Hinge || support.kind == SideSupport::Kind::Clamp)
      sideHolds[k] = support.components;
    else if (support.kind == SideSupport::Kind::Symmetry && sim.componentConstraints())
      sideHolds[k] = 1u << sim.componentConstraints()->planes()[size_t(k)].axis;
  }
  const unsigned pinHolds = sim.parameters().pinComponents;

  const LayerRange &mu = s.movingU(), &mv = s.movingV();
  static const std::vector<int> noPins;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const Eigen::Index k = Eigen::Index(i) * cols + j;
      // the unknown this point is (itself or, for a periodic copy, the one it repeats): pinned?
      const int li = s.movingLayerU(i), lj = s.movingLayerV(j);
      const std::vector<int>& of =
          li >= 0 && lj >= 0 ? pinsOf[size_t(Eigen::Index(li - mu.first) * mv.count + (lj - mv.first))] : noPins;
      const bool in[4] = {i < bands[0].width, i >= rows - bands[1].width, j < bands[2].width,
                          j >= cols - bands[3].width};
      // component c goes to the pins and sides that hold c, in equal shares; a pinned point
      // whose pins hold c belongs to them alone (their points are left out of the bands); what
      // nothing here holds is the equilibrium's residual
      for (int c = 0; c < 3; ++c) {
        const double fc = f(k, c);
        if (!of.empty() && (pinHolds & (1u << c))) {
          for (int p : of) r.pins[size_t(p)][c] += fc / double(of.size());
          continue;
        }
        int count = 0;
        for (int side = 0; side < 4; ++side) count += in[side] && (sideHolds[side] & (1u << c)) ? 1 : 0;
        if (count == 0) {
          r.elsewhere[c] += fc;
          continue;
        }
        for (int side = 0; side < 4; ++side)
          if (in[side] && (sideHolds[side] & (1u << c))) r.sides[size_t(sideOf[side])].force[c] += fc / double(count);
      }
    }
  return r;
}

}  // namespace bsdeform
