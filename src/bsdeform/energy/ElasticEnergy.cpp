// SPDX-License-Identifier: MIT
#include "bsdeform/energy/ElasticEnergy.h"

#include "bsdeform/base/HugePages.h"

namespace bsdeform {

ElasticEnergy::~ElasticEnergy() = default;

void ElasticEnergy::displacementNet(const SplineSpace& space, const ControlNet& d, ControlNet& out) {
  out.setZero(space.netSize(), 3);
  space.scatterMoving(d, out);
  space.completeNet(out, nullptr);  // the homogeneous form: derived layers Z d, copies
}

// ---- the paper's energy ----

PaperEnergy::PaperEnergy(const SplineSpace& space, const StiffnessStencil& stencil, const ControlNet& rest,
                         bool restReference, bool lumpedMass, double mass)
    : m_space(space), m_stencil(stencil), m_rest(rest), m_restReference(restReference) {
  if (restReference) {
    allocateNet(m_c0, space.numMoving());
    stencil.applyMoving(rest, m_c0);
  } else {
    m_c0.setZero(space.numMoving(), 3);
  }
  // With NODAL mass, or LUMPED mass where every row sum is the interior one, M is a multiple of
  // the identity and the symbol bound holds; a FREE side makes the lumped edge masses smaller,
  // and derived layers (SIMPLY_SUPPORTED, BUILT_IN) keep their mass: M = T^T W T is not
  // diagonal there (EdgeMass), and lambda_max(M^-1 A_II) is bounded on the whole layer space.
  const Boundaries& bc = space.boundaries();
  const bool anyFree = bc.uMin == Boundary::Free || bc.uMax == Boundary::Free || bc.vMin == Boundary::Free ||
                       bc.vMax == Boundary::Free;
  m_uniformMass = !(lumpedMass && anyFree) && !space.hasDerived();
  const double perPoint = lumpedMass ? mass * space.basisU().spacing() * space.basisV().spacing() : mass;
  if (m_uniformMass)
    m_lambda = stencil.eigenvalueBound() / perPoint;
  else if (lumpedMass)
    m_lambda = stencil.elementEigenvalueBound() / mass;
  else
    m_lambda = stencil.symbolBound() / mass;  // derived layers, nodal mass
}

double PaperEnergy::energy(const ControlNet& net) const {
  // exact for a quadratic: W(rest) + g_r . D + 1/2 D A D with W(rest) = 0
  const ControlNet D = net - m_rest;  // held points: exactly zero
  ControlNet AD;
  m_stencil.applyMoving(D, AD);
  const ControlNet Dm = m_space.gatherMoving(D);
  double w = 0.5 * Dm.cwiseProduct(AD).sum();
  if (!m_restReference) {
    ControlNet gr;
    m_stencil.applyMoving(m_rest, gr);
    w += Dm.cwiseProduct(gr).sum();
  }
  return w;
}

void PaperEnergy::gradient(const ControlNet& net, ControlNet& out) const {
  m_stencil.applyMoving(net, out);
  if (m_restReference) out -= m_c0;
}

void PaperEnergy::hessianProduct(const ControlNet&, const ControlNet& d, ControlNet& out) const {
  ControlNet dn;
  displacementNet(m_space, d, dn);
  m_stencil.applyMoving(dn, out);
}

double PaperEnergy::eigenvalueBound(const ControlNet&) const { return m_lambda; }

// ---- the shell ----

ShellModelEnergy::ShellModelEnergy(const SplineSpace& space, const ControlNet& rest, const ShellMaterial& material)
    : m_space(space), m_shell(space, rest, material), m_netMass(m_shell.lumpedMass()) {
  space.foldMap(m_foldStart, m_foldEntries);  // T: every net point in terms of the unknowns
}

void ShellModelEnergy::fold(const ControlNet& g, ControlNet& out) const {
  out.setZero(m_space.numMoving(), 3);
  for (Eigen::Index p = 0; p < m_space.netSize(); ++p)
    for (int a = m_foldStart[size_t(p)]; a < m_foldStart[size_t(p) + 1]; ++a)
      out.row(m_foldEntries[size_t(a)].first) += m_foldEntries[size_t(a)].second * g.row(p);
}

void ShellModelEnergy::gradient(const ControlNet& net, ControlNet& out) const {
  m_shell.gradient(net, m_netScratch[0]);
  fold(m_netScratch[0], out);
}

double ShellModelEnergy::energyAndGradient(const ControlNet& net, ControlNet& out) const {
  double energy = 0.0;
  m_shell.gradient(net, m_netScratch[0], &energy);
  fold(m_netScratch[0], out);
  return energy;
}

void ShellModelEnergy::hessianProduct(const ControlNet& net, const ControlNet& d, ControlNet& out) const {
  displacementNet(m_space, d, m_netScratch[1]);
  m_shell.hessianProduct(net, m_netScratch[1], m_netScratch[0]);
  fold(m_netScratch[0], out);
}

}  // namespace bsdeform
