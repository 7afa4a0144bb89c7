// SPDX-License-Identifier: MIT
#pragma once
/// @file BarrierContact.h
/// Barrier contact (Incremental Potential Contact; Li et al. 2020, C-IPC: Li, Kaufman, Jiang 2021)
/// of a spline surface with the obstacles of a ContactWorld and, when asked, with itself,
/// through its CollisionProxy (docs/math.md §18). A force with a potential, a gradient and a
/// Hessian (exact, or each pair's projected to PSD where the receiver asks for a definite one),
/// for the implicit steps, and a bound on every trial step:
/// admissibleFraction() cuts a step to the largest fraction over which no proxy vertex, edge or
/// triangle comes within the offset of an obstacle's or of another part of the proxy (additive
/// CCD), so the line search of the implicit step never crosses.

#include <array>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "bsdeform/contact/BroadPhase.h"
#include "bsdeform/contact/CollisionProxy.h"
#include "bsdeform/contact/Contact.h"
#include "bsdeform/forces/Force.h"

namespace bsdeform {

/// A mesh that does not move over the step (start = end), each undirected edge once.
ContactMesh staticContactMesh(const TriangleMesh& mesh);

struct BarrierContactParameters {
  double offset = 0.01;    ///< ξ > 0, metres (world): the proxy keeps this far from obstacles and itself
  double dhat = 1e-3;      ///< d̂ > 0, metres: the barrier acts between ξ and ξ + d̂
  bool selfContact = false;
  int samplesPerSpan = 2;  ///< the proxy's resolution (CollisionProxy)
  /// μ ≥ 0: IPC's lagged smooth friction (Friction.h) on the pairs in contact at the start of each
  /// step; 0: none
  double friction = 0.0;
  /// ε_v > 0, m/s: slips slower than this are smoothed static friction (the force grows from 0 to
  /// μλ over a slip of ε_v h in a step)
  double epsv = 1e-3;
  double mass = 1.0;       ///< the surface's mass (kg), for the barrier stiffness's scale
  /// Whether the mass is the model's, LoadContext::massPerArea times restArea when the stiffness
  /// is first chosen, instead of `mass`: a model rebuilt with another mass keeps the same force
  /// (what the nodes do).
  bool modelMass = false;
  /// Whether each pair's Hessian is projected to positive semidefinite when the Jacobian's
  /// receiver asks for a definite one (JacobianSink::wantsDefinite: the Newton matrix after the
  /// exact one failed); false (tests): the pair Hessians as they are, always (the exact Hessian
  /// of the potential for obstacle contact).
  bool projectHessian = true;
};

class BarrierContactForce : public Force {
 public:
  /// @throws std::invalid_argument naming the parameter and the value
  BarrierContactForce(std::shared_ptr<const ContactWorld> world, const BarrierContactParameters& p);
  ~BarrierContactForce() override;

  /// On the position; with friction also on the velocity (the slip over the step).
  unsigned dependence() const override;
  /// -∂Φ/∂P, Φ = κ Σ_pairs b (the mollified edge–edge pairs times their mollifier), plus the
  /// friction potential Σ μ λ f0(|u|) of the pairs frozen at beginStep() (Friction.h), u their
  /// tangential slip from ctx.previous to ctx.current.
  void addLoad(const LoadContext& ctx, ControlNet& load) const override;
  /// Each pair's Hessian (projected to PSD where the sink asks for a definite Jacobian,
  /// JacobianSink::wantsDefinite, and projectHessian is set; exact otherwise) pushed to the
  /// control points through the proxy's weights. Self-contact pairs couple two parts of the
  /// surface that share no element: their whole Hessian goes to the sink, the blocks between the
  /// two parts included (the tangent takes them into its pattern: Newton converges
  /// quadratically in self-contact only with them).
  /// Friction's Hessian (PSD by construction) likewise; it is a function of the slip, so its share
  /// is velocityScale × stepSize × ∂²D/∂x² (∂²D/∂x² itself in the implicit step).
  bool hasJacobian() const override { return true; }
  void addJacobian(const LoadContext& ctx, double velocityScale, JacobianSink& sink) const override;
  bool potential(const LoadContext& ctx, double& value) const override;
  /// The barrier's potential (friction stores none), unless an obstacle or the frame moved since
  /// the first call.
  bool storedEnergy(const LoadContext& ctx, double& value) const override;
  double admissibleFraction(const LoadContext& ctx, const ControlNet& to) const override;
  /// An obstacle that moved since the last step (its TriangleTree refitted: the same triangles,
  /// new positions) is swept from its pose at the end of the last step to its pose now: each call
  /// moves it as far as additive CCD lets it with the proxy at ctx.current (docs/math.md §18.4).
  double advanceObstacles(const LoadContext& ctx) const override;
  double jointAdvanceFraction(const LoadContext& ctx, const ControlNet& to, double obstacleFraction) const override;
  double advanceObstaclesBy(const LoadContext& ctx, double fraction) const override;
  bool limitsSteps() const override { return true; }
  /// Checks the deviation bound and the start's clearance, adapts κ, and freezes the friction
  /// pairs (those within the barrier's reach, with their normal forces at this state).
  std::string beginStep(const LoadContext& ctx) const override;
  /// {κ, its cap, the last smallest distance of a pair within reach (-1: none)} once κ is set;
  /// empty before.
  std::vector<double> adaptedState() const override;
  void setAdaptedState(const std::vector<double>& state) const override;
  /// The stiffness, its cap and the last smallest distance rounded. The obstacles' poses are the
  /// world's as given: a world that is to resume bit for bit from a file gives its vertices at
  /// the file's precision (the nodes' SceneObstacles do).
  void roundAdaptedState(double (*round)(double)) const override;
  const char* backwardEulerOnly() const override {
    return "barrier contact (COLLISION with method BARRIER) needs integrator BACKWARD_EULER: the explicit scheme "
           "has no line search to keep the proxy from crossing";
  }

  const BarrierContactParameters& parameters() const { return m_params; }
  /// The barrier stiffness κ now (adapted between steps, docs/math.md §18).
  double stiffness() const;
  /// The smallest distance of a pair at the last evaluation (infinity when no pair is within
  /// the barrier's reach, offset + dhat).
  double lastMinimumDistance() const;
  /// The proxy's deviation bound at the last beginStep().
  double lastDeviationBound() const;
  /// How many times the candidate pairs were searched for anew (the rest of the queries were
  /// answered from the kept ones: State::Candidates).
  long candidateSearches() const;
  /// Where this force's time went (wall seconds on the calling thread, the work it hands to
  /// kernel threads inside), accumulated until resetCosts(): issue 35's "broad phase, CCD,
  /// barrier assembly".
  struct Costs {
    double proxy = 0.0;       ///< the proxy's vertices from the control net
    double broadPhase = 0.0;  ///< candidate pairs: searched anew or narrowed from the kept ones
    double pairs = 0.0;       ///< the pairs' barrier and friction terms (value, gradient, PSD Hessian)
    double push = 0.0;        ///< the Jacobian's blocks summed per element pair and handed to the tangent
    double ccd = 0.0;         ///< continuous collision checks of the candidates (line search, sweeps)
    /// Candidate pairs whose terms were computed: at the first evaluation at a net the
    /// candidates that the distance bounds (Distance.h) do not put beyond the reach, at the
    /// later ones the pairs within reach
    long pairsComputed = 0;
  };
  const Costs& costs() const;
  void resetCosts() const;
  /// The friction pairs frozen at the last beginStep(), and the sum of their normal forces (N).
  size_t frictionPairCount() const;
  double frictionNormalForce() const;

 private:
  struct State;
  /// One pair's barrier: its points (proxy vertices, -1 for an obstacle's), value, and gradient
  /// and Hessian over the 4 points' 12 world coordinates.
  struct Term {
    std::array<Eigen::Index, 4> vertex{};
    bool friction = false;  ///< a friction pair's (its Hessian is in the slip: addJacobian())
    double value = 0.0;
    Eigen::Matrix<double, 12, 1> grad;
    Eigen::Matrix<double, 12, 12> hess;
  };
  void prepare(const LoadContext& ctx) const;
  void proxyWorld(const ControlNet& net, Eigen::MatrixX3d& out) const;
  /// The proxy at ctx.current (world frame) and the candidate pairs within reach of it: one set
  /// per obstacle, the self pairs last (valid until the next call).
  const std::vector<ContactCandidates>& gather(const LoadContext& ctx) const;
  /// The pairs the broad phase finds with `inflation` between the proxy's mesh (start to end)
  /// and each obstacle, and itself: from the kept candidates when they cover them (State).
  const std::vector<ContactCandidates>& candidatesWithin(double inflation) const;
  /// The self pairs of `mesh` (candidatePairs with `inflation`) but for those whose primitives
  /// lie within the reach (thickness + dhat) of each other at rest (docs/math.md §18.2):
  /// neighbours in the sheet, not contacts; left out before the pairs are sorted.
  void selfCandidatesApartAtRest(const ContactMesh& mesh, double inflation, ContactCandidates& out) const;
  /// fn(term) for every pair within reach at ctx.current, with derivatives up to `order`; then,
  /// when `withFriction`, for every frozen friction pair. `projected`: each barrier pair's
  /// Hessian projected to positive semidefinite (its moving points' block). Of a Hessian only
  /// the blocks between the term's moving points (vertex >= 0) are given: on kernel threads the
  /// others are not set.
  void terms(const LoadContext& ctx, int order, const std::function<void(const Term&)>& fn,
             bool withFriction = true, bool projected = false) const;
  /// Freezes the friction pairs at ctx.current (beginStep()).
  void freezeFriction(const LoadContext& ctx) const;
  /// A candidate pair as terms() and freezeFriction() visit it (forEachPair()).
  struct PairSite;
  /// visit(site) for every pair of `candidates` (gather()), obstacle by obstacle and the self
  /// pairs last, in each: vertex–triangle, triangle–vertex, edge–edge. The one loop both walk.
  /// Only the pairs at places [begin, end) of that order (a part of them, on a kernel thread).
  /// `beyond` > 0: pairs that a cheap lower bound of their distance (a plane, a line, bounding
  /// spheres) puts farther than `beyond` are not visited.
  template <typename Visit>
  void forEachPair(const std::vector<ContactCandidates>& candidates, Visit&& visit, size_t begin = 0,
                   size_t end = std::numeric_limits<size_t>::max(), double beyond = 0.0) const;
  std::shared_ptr<const ContactWorld> m_world;
  BarrierContactParameters m_params;
  std::shared_ptr<State> m_state;  // mutable: the proxy, κ, caches (the force is const in a step)
};

}  // namespace bsdeform
