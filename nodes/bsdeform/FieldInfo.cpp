// SPDX-License-Identifier: MIT
#include "bsdeform/FieldInfo.h"

#include <cmath>
#include <cstring>
#include <sstream>
#include <utility>

#include "bsdeform/SoBSplineDeformSurface.h"
#include "bsdeform/SoForceField.h"

namespace bsdeform {

namespace {
constexpr double kOpen = HUGE_VAL;
constexpr unsigned bit(SoForceField::Type t) { return 1u << t; }
const char* const kSurface = "SoBSplineDeformSurface";
const char* const kForce = "SoForceField";

constexpr unsigned kScaled = bit(SoForceField::UNIFORM) | bit(SoForceField::POINT) | bit(SoForceField::REGION) |
                             bit(SoForceField::GRAVITY);
// SoBSplineDeformSurface: bit (1 << energy) for each energy model that reads the field
constexpr unsigned kPaper = 1u << SoBSplineDeformSurface::PAPER_ENERGY;
constexpr unsigned kShell = 1u << SoBSplineDeformSurface::SHELL;
constexpr unsigned kPenalty = bit(SoForceField::PLANE_COLLISION) | bit(SoForceField::SPHERE_COLLISION);

std::vector<FieldInfo> makeTable() {
  const char* S = kSurface;
  const char* F = kForce;
  return {
      // node, name, meaning, unit, symbol, range, min, max, usedBy, restarts, live
      {S, "numUControlPoints", "Free control points along u (the net has N1 + 2 n1 points along u).", "", "N1", ">= 1", 1, 100000, 0, true, false, "numU"},
      {S, "numVControlPoints", "Free control points along v.", "", "N2", ">= 1", 1, 100000, 0, true, false, "numV"},
      {S, "uDegree", "B-spline degree along u.", "", "n1", "1..7", 1, 7, 0, true, false, "degreeU"},
      {S, "vDegree", "B-spline degree along v.", "", "n2", "1..7", 1, 7, 0, true, false, "degreeV"},
      {S, "w10", "Resistance to stretching along u: weight of |S_u - S0_u|² in the deformation energy.", "energy per length²", "ω10", ">= 0", 0, kOpen, kPaper, false, false},
      {S, "w01", "Resistance to stretching along v: weight of |S_v - S0_v|².", "energy per length²", "ω01", ">= 0", 0, kOpen, kPaper, false, false},
      {S, "w11", "Resistance to twist: weight of |S_uv - S0_uv|².", "energy per length²", "ω11", ">= 0", 0, kOpen, kPaper, false, false},
      {S, "w20", "Resistance to bending along u: weight of |S_uu - S0_uu|².", "energy per length²", "ω20", ">= 0", 0, kOpen, kPaper, false, false},
      {S, "w02", "Resistance to bending along v: weight of |S_vv - S0_vv|².", "energy per length²", "ω02", ">= 0", 0, kOpen, kPaper, false, false},
      {S, "energy", "PAPER: the paper's energy (eq. 7) with the weights ω. SHELL: the Kirchhoff–Love thin shell of the material (material, youngsModulus … density; SI units: mass ρ t per rest area, damping a rate in 1/s, loads per unit rest area or length).", "", "", "PAPER, SHELL", 0, 0, 0, true, false},
      {S, "material", "SHELL: the strain energy per volume. SAINT_VENANT_KIRCHHOFF: S = C:E with the plane-stress moduli, membrane ∝ t and bending ∝ t³/12 (for small strains; it softens in compression and stiffens without bound in tension). NEO_HOOKEAN: compressible neo-Hookean (μ, λ from E and ν), plane stress by condensing the thickness stretch, integrated through the thickness (3 points): the same for small strains, for stretches well beyond them (rubber, membranes inflated to twice their size).", "", "", "SAINT_VENANT_KIRCHHOFF, NEO_HOOKEAN", 0, 0, kShell, true, false},
      {S, "youngsModulus", "SHELL: Young's modulus of the material.", "Pa", "E", "> 0", 1e-300, kOpen, kShell, true, false},
      {S, "poissonRatio", "SHELL: Poisson's ratio.", "", "ν", "[0, 0.5)", 0, 0.4999999, kShell, true, false},
      {S, "thickness", "SHELL: thickness of the sheet (membrane stiffness ∝ t, bending ∝ t³).", "m", "t", "> 0", 1e-300, kOpen, kShell, true, false},
      {S, "density", "SHELL: mass per volume; the sheet has ρ t per unit rest area.", "kg/m³", "ρ", "> 0", 1e-300, kOpen, kShell, true, false},
      {S, "massModel", "NODAL: M = m I, mass m per control point. LUMPED: M = m h1 h2 I, m per unit parameter area.", "", "M", "NODAL, LUMPED", 0, 0, kPaper, false, false},
      {S, "mass", "Mass per control point (NODAL) or per unit parameter area (LUMPED).", "mass", "m", "> 0", 1e-300, kOpen, kPaper, false, false},
      {S, "damping", "Viscous damping: PAPER, same convention as mass; SHELL, a mass-proportional rate (C = c M, in 1/s).", "mass per time", "c", ">= 0", 0, kOpen, 0, false, false},
      {S, "timeStep", "Simulated time per step; the explicit scheme takes sub-steps below its stability limit.", "s", "Δt", "> 0", 1e-300, kOpen, 0, false, false},
      {S, "integrator", "EXPLICIT: central differences, sub-stepped. IMPLICIT: Newmark (unconditionally stable, second order). BACKWARD_EULER (either energy): the incremental potential minimised by Newton with every force inside (the barrier contact needs it); dissipative, for cloth.", "", "", "EXPLICIT, IMPLICIT, BACKWARD_EULER", 0, 0, 0, false, false},
      {S, "maxSubSteps", "EXPLICIT: a step that needs more sub-steps is refused instead of running for minutes.", "", "", ">= 1", 1, 2147483647, 0, false, false},
      {S, "newtonTolerance", "BACKWARD_EULER, and SHELL's IMPLICIT and static solve: Newton stops when the residual, relative to the forces it balances, is below this.", "", "", "(0, 1)", 1e-300, 0.9999999, 0, false, false},
      {S, "maxNewtonIterations", "BACKWARD_EULER, and SHELL's IMPLICIT: a step whose Newton iteration needs more iterations fails (reported, the last valid state kept).", "", "", ">= 1", 1, 2147483647, 0, false, false},
      {S, "newtonVelocityTolerance", "BACKWARD_EULER: Newton has converged when its largest update divided by the time step is below this.", "m/s", "", "> 0", 1e-300, kOpen, 0, false, false},
      {S, "nonlinearSolver", "BACKWARD_EULER: NEWTON factorises the tangent (every force's Jacobian inside) at the iterates, a few iterations a step; LBFGS (quasi-Newton, Liu, Bouaziz and Kavan 2017) factorises one matrix per model and time step (the mass over the step squared plus the rest stiffness made the same in every direction) and learns the rest from the last 8 gradients: more iterations, each a gradient and a solve, 2 to 7 times faster for cloth without barrier contact. LBFGS allows 10 x maxNewtonIterations iterations and converges when two updates in a row divided by the time step are below newtonVelocityTolerance. With a BARRIER collision, holdUMin ... holdPins or SYMMETRY sides it starts from each step's first tangent instead (little gain over NEWTON there).", "", "", "NEWTON, LBFGS", 0, 0, 0, false, false},
      {S, "reference", "REST: energy of the displacement S - S_rest. ABSOLUTE: the paper's energy of S itself.", "", "", "REST, ABSOLUTE", 0, 0, kPaper, false, false},
      {S, "boundaryUMin", "Side u = 0: CLAMPED (n outer layers held, as in the paper: S and n-1 cross derivatives fixed), FREE (natural boundary), PERIODIC (with boundaryUMax), SIMPLY_SUPPORTED (the edge curve held, free to turn: a hinge; holdUMin picks its components), BUILT_IN (the edge curve and the cross derivative held: an engineering clamp) or SYMMETRY (SHELL: the static solve, arc length, BACKWARD_EULER and IMPLICIT, not EXPLICIT; the rest net mirror-symmetric about a coordinate plane through the edge, and so the solution).", "", "", "CLAMPED, FREE, PERIODIC, SIMPLY_SUPPORTED, BUILT_IN, SYMMETRY", 0, 0, 0, true, false},
      {S, "boundaryUMax", "Side u = 1, as boundaryUMin.", "", "", "CLAMPED, FREE, PERIODIC, SIMPLY_SUPPORTED, BUILT_IN, SYMMETRY", 0, 0, 0, true, false},
      {S, "boundaryVMin", "Side v = 0, as boundaryUMin.", "", "", "CLAMPED, FREE, PERIODIC, SIMPLY_SUPPORTED, BUILT_IN, SYMMETRY", 0, 0, 0, true, false},
      {S, "boundaryVMax", "Side v = 1, as boundaryUMin.", "", "", "CLAMPED, FREE, PERIODIC, SIMPLY_SUPPORTED, BUILT_IN, SYMMETRY", 0, 0, 0, true, false},
      {S, "holdUMin", "The world components a SIMPLY_SUPPORTED or BUILT_IN side u = 0 holds (of the edge curve, and for BUILT_IN of the cross derivative too): X | Y | Z is the side kind itself; two of them a rigid diaphragm (a cylinder along y ends on (X | Z)), one a roller. Exact, by elimination. SHELL: the static solve, arc length, BACKWARD_EULER and IMPLICIT (not EXPLICIT).", "", "", "X, Y, Z (a bit mask)", 0, 0, 2, true, false},
      {S, "holdUMax", "As holdUMin, side u = 1.", "", "", "X, Y, Z (a bit mask)", 0, 0, 2, true, false},
      {S, "holdVMin", "As holdUMin, side v = 0.", "", "", "X, Y, Z (a bit mask)", 0, 0, 2, true, false},
      {S, "holdVMax", "As holdUMin, side v = 1.", "", "", "X, Y, Z (a bit mask)", 0, 0, 2, true, false},
      {S, "holdPins", "The world components the pins hold (one pin holding one component takes out a last free translation, the axial slide of a roof on two diaphragms, which the static solve and arc length refuse, loaded or not). Fewer than X | Y | Z: SHELL, the static solve, arc length, BACKWARD_EULER and IMPLICIT (not EXPLICIT).", "", "", "X, Y, Z (a bit mask)", 0, 0, 2, true, false, "pinComponents"},
      {S, "motionUMin", "SHELL, BACKWARD_EULER: the map (as a Transform's matrix) whose image of their rest positions the n layers a CLAMPED side u = 0 holds follow: connect a ComposeMatrix driven by the clock to turn or carry an edge (a sheet twisted by turning one end). Read before every step and reached at its end; the move is checked by the barrier's CCD first. Identity and unconnected: held at rest. The sides next to a moved side must be FREE or PERIODIC, or moved by the same map.", "", "", "an affine 4 x 4 matrix", 0, 0, kShell, false, false},
      {S, "motionUMax", "As motionUMin, side u = 1.", "", "", "an affine 4 x 4 matrix", 0, 0, kShell, false, false},
      {S, "motionVMin", "As motionUMin, side v = 0.", "", "", "an affine 4 x 4 matrix", 0, 0, kShell, false, false},
      {S, "motionVMax", "As motionUMin, side v = 1.", "", "", "an affine 4 x 4 matrix", 0, 0, kShell, false, false},
      {S, "pins", "Parameter points (u, v); each holds the control points of its knot span.", "", "", "(u, v) in [0, 1]²", 0, 1, 0, false, false},
      {S, "start", "SECOND_ORDER: P(-Δt) = P(0) + Δt²/2 a(0), a consistent release from rest. PAPER: P(-Δt) = P(0).", "", "", "SECOND_ORDER, PAPER", 0, 0, 0, false, false},
      {S, "restShape", "Rest net generated when restNet is empty, centred at the origin with axis z; shapes other than PLANE impose the boundaries they need.", "", "S0", "PLANE, CYLINDER, CONE, SPHERE, ELLIPSOID, TORUS", 0, 0, 0, true, false},
      {S, "radius", "CYLINDER, CONE (base), SPHERE radius; TORUS: distance to the tube's centre.", "length", "R", "> 0", 0, kOpen, 0, true, false},
      {S, "height", "CYLINDER and CONE height (z from -H/2 to H/2).", "length", "H", "> 0", 0, kOpen, 0, true, false},
      {S, "minorRadius", "TORUS tube radius.", "length", "r", "> 0", 0, kOpen, 0, true, false},
      {S, "radii", "ELLIPSOID semi-axes along x, y, z.", "length", "(a, b, c)", "> 0 each", 0, kOpen, 0, true, false},
      {S, "on", "Follow Coin's realTime, as SoElapsedTime does: whoever drives it (any Coin viewer, bsdeform-viewer's Play / Pause, which never write this field) animates the surface. FALSE: it stands still unless stepped (Step, bsdeform-run, Python).", "", "", "TRUE, FALSE", 0, 0, 0, false, false},
      {S, "speed", "Simulated seconds per second of realTime while on (bsdeform-viewer's speed box scales realTime itself and never writes this field).", "", "", "> 0", 0, 1e4, 0, false, false},
      {S, "reset", "Trigger: back to the rest state at t = 0.", "", "", "", 0, 0, 0, false, false},
      {S, "restNet", "Rest control net, (N1 + 2 n1)(N2 + 2 n2) points u-major; empty: the plane (u, v, 0) or restShape.", "length", "P0", "", 0, 0, 0, true, true},
      {S, "controlNet", "Current control net (state); empty: the rest net.", "length", "P(t)", "", 0, 0, 0, false, true},
      {S, "previousNet", "Control net one sub-step earlier (state); empty: controlNet.", "length", "P(t - Δt)", "", 0, 0, 0, false, true},
      {S, "simulationTime", "Simulated time of controlNet.", "s", "t", ">= 0", 0, kOpen, 0, false, true},
      {S, "stepCount", "Steps taken since rest.", "", "", ">= 0", 0, 2147483647, 0, false, true},
      {S, "forceState", "What the forces adapt between steps (state, written with the nets so that a resumed run takes the same steps): per force its count of values, then the values (COLLISION BARRIER: its stiffness κ, κ's cap, the last smallest distance of a pair within its reach (thickness + dhat), or -1 when none, then where it last saw each obstacle: their count, and per obstacle its vertex count and coordinates); empty: as made.", "", "", "", 0, 0, 0, false, true},
      {S, "forces", "SoForceField engines acting on the surface.", "", "f", "", 0, 0, 0, false, false},

      {F, "type", "The kind of force; each type reads only some of the fields below.", "", "", "UNIFORM, POINT, REGION, EXPRESSION, GRAVITY, SPRING, DRAG, PRESSURE, PLANE_COLLISION, SPHERE_COLLISION, COLLISION", 0, 0, 0, false, false},
      {F, "on", "FALSE switches the force off.", "", "", "TRUE, FALSE", 0, 0, 0, false, false},
      {F, "force", "Direction and size: force density (UNIFORM, REGION), point force (POINT), acceleration (GRAVITY); times magnitude.", "force per unit area, force, or acceleration", "f", "", -kOpen, kOpen, kScaled, false, false},
      {F, "magnitude", "Scale of force, of the expression, of gravity; the pressure p of PRESSURE.", "", "", "finite", -kOpen, kOpen, kScaled | bit(SoForceField::EXPRESSION) | bit(SoForceField::PRESSURE), false, false},
      {F, "point", "Parameter point (u, v) where a POINT force acts or a SPRING is attached.", "", "(u0, v0)", "[0, 1]²", 0, 1, bit(SoForceField::POINT) | bit(SoForceField::SPRING), false, false},
      {F, "regionMin", "Lower corner (u0, v0) of the REGION rectangle.", "", "", "[0, 1]², <= regionMax", 0, 1, bit(SoForceField::REGION), false, false},
      {F, "regionMax", "Upper corner (u1, v1) of the REGION rectangle.", "", "", "[0, 1]², >= regionMin", 0, 1, bit(SoForceField::REGION), false, false},
      {F, "expression", "x, y, z force density as three muParser formulas of u, v, x, y, z, t (pi is defined).", "force per unit area", "", "3 formulas", 0, 0, bit(SoForceField::EXPRESSION), false, false},
      {F, "anchor", "Point the SPRING pulls toward.", "length", "", "", -kOpen, kOpen, bit(SoForceField::SPRING), false, false},
      {F, "center", "PLANE_COLLISION: a point of the plane. SPHERE_COLLISION: the centre.", "length", "", "", -kOpen, kOpen, kPenalty, false, false},
      {F, "normal", "PLANE_COLLISION plane normal, pointing to the free side.", "", "", "not zero", -kOpen, kOpen, bit(SoForceField::PLANE_COLLISION), false, false},
      {F, "radius", "SPHERE_COLLISION radius.", "length", "", "> 0", 0, kOpen, bit(SoForceField::SPHERE_COLLISION), false, false},
      {F, "stiffness", "SPRING constant k; collision penalty per unit area and depth.", "force per length (SPRING), pressure per length (collisions)", "k", ">= 0", 0, kOpen, bit(SoForceField::SPRING) | kPenalty | bit(SoForceField::COLLISION), false, false},
      {F, "coefficient", "DRAG: force density = -coefficient · velocity.", "force per unit area per speed", "", ">= 0", 0, kOpen, bit(SoForceField::DRAG), false, false},
      {F, "obstacles", "COLLISION: subgraphs the surface collides with.", "", "", "", 0, 0, bit(SoForceField::COLLISION), false, false},
      {F, "obstacleNames", "COLLISION: DEF names of further obstacles, looked up in the surface's scene.", "", "", "", 0, 0, bit(SoForceField::COLLISION), false, false},
      {F, "thickness", "COLLISION: contact offset from the obstacles.", "length", "", ">= 0", 0, kOpen, bit(SoForceField::COLLISION), false, false},
      {F, "damping", "COLLISION: normal damping per unit world area (pressure per approach speed).", "pressure per speed", "", ">= 0", 0, kOpen, bit(SoForceField::COLLISION), false, false},
      {F, "friction", "COLLISION: Coulomb friction coefficient (PENALTY: the law of docs/math.md §13; BARRIER: IPC's lagged smooth friction, §18.3).", "", "μ", ">= 0", 0, kOpen, bit(SoForceField::COLLISION), false, false},
      {F, "method", "COLLISION: PENALTY, a force proportional to the depth (every integrator); BARRIER, IPC's barrier on a collision proxy of the spline with steps cut by continuous collision checks, so nothing ever crosses (BACKWARD_EULER only).", "", "", "PENALTY, BARRIER", 0, 0, bit(SoForceField::COLLISION), false, false},
      {F, "dhat", "COLLISION BARRIER: the barrier acts between thickness and thickness + dhat from an obstacle (or the surface itself).", "m", "d̂", "> 0", 1e-300, kOpen, bit(SoForceField::COLLISION), false, false},
      {F, "selfContact", "COLLISION BARRIER: the surface also collides with itself (proxy triangles and edges that share no vertex and lie more than thickness + dhat apart at rest).", "", "", "TRUE, FALSE", 0, 0, bit(SoForceField::COLLISION), false, false},
      {F, "proxySamples", "COLLISION BARRIER: intervals of the collision proxy per knot span and direction; the spline lies within (max|Δ²P| terms)/(8 r²) of it, which must stay below thickness.", "", "r", "1..16", 1, 16, bit(SoForceField::COLLISION), false, false},
      {F, "epsv", "COLLISION BARRIER: friction's velocity threshold: slips slower than epsv are static friction, smoothed (the force grows from 0 to friction times the normal force over a slip of epsv times the time step).", "m/s", "ε_v", "> 0", 1e-300, kOpen, bit(SoForceField::COLLISION), false, false},
      {F, "frame", "WORLD: force, anchor, center, normal, radius and the expression's x y z and result are in world coordinates, through the Transforms above the surface. LOCAL: in the surface's own coordinates (its control net's).", "", "", "WORLD, LOCAL", 0, 0, kScaled | bit(SoForceField::POINT) | bit(SoForceField::EXPRESSION) | bit(SoForceField::SPRING) | kPenalty, false, false},
  };
}

// Markdown cell text: a '|' would end the cell.
std::string cell(const char* text) {
  std::string s;
  for (const char* p = text; *p; ++p) s += *p == '|' ? std::string("\\|") : std::string(1, *p);
  return s;
}
}  // namespace

const std::vector<FieldInfo>& fieldInfos() {
  static const std::vector<FieldInfo> table = makeTable();
  return table;
}

const FieldInfo* findFieldInfo(const char* node, const char* field) {
  for (const FieldInfo& f : fieldInfos())
    if (std::strcmp(f.node, node) == 0 && std::strcmp(f.name, field) == 0) return &f;
  return nullptr;
}

const FieldInfo* surfaceFieldOfParameter(const std::string& parameter) {
  for (const FieldInfo& f : fieldInfos())
    if (std::strcmp(f.node, kSurface) == 0 && parameter == (f.parameter ? f.parameter : f.name)) return &f;
  return nullptr;
}

bool surfaceFieldUses(int energy, const char* field) {
  const FieldInfo* f = findFieldInfo(kSurface, field);
  return f && (f->usedBy == 0 || (energy >= 0 && energy < 32 && (f->usedBy >> energy) & 1u));
}

bool forceFieldUses(int type, const char* field) {
  const FieldInfo* f = findFieldInfo(kForce, field);
  return f && (f->usedBy == 0 || (type >= 0 && type < 32 && (f->usedBy >> type) & 1u));
}

std::string fieldReferenceMarkdown() {
  // the type names as the node spells them (initNodes() must have run)
  std::vector<std::pair<int, std::string>> typeNames;
  SoForceField* probe = new SoForceField;
  probe->ref();
  for (int k = 0; k < probe->type.getNumEnums(); ++k) {
    SbName name;
    const int value = probe->type.getEnum(k, name);
    typeNames.emplace_back(value, name.getString());
  }
  probe->unref();
  std::ostringstream out;
  for (const char* node : {kSurface, kForce}) {
    const bool force = node == kForce;
    out << "### " << node << "\n\n";
    out << (force ? "| field | meaning | unit | range | symbol | read by types |\n|---|---|---|---|---|---|\n"
                  : "| field | meaning | unit | range | symbol | energy |\n|---|---|---|---|---|---|\n");
    for (const FieldInfo& f : fieldInfos()) {
      if (f.node != node) continue;
      std::string notes = cell(f.meaning);
      if (f.restarts) notes += " Changing it restarts the simulation from rest.";
      if (f.live) notes += " Kept current by the node.";
      out << "| `" << f.name << "` | " << notes << " | " << cell(f.unit) << " | " << cell(f.range) << " | " << cell(f.symbol)
          << " |";
      if (force) {
        std::string types;
        for (const auto& t : typeNames)
          if ((f.usedBy >> t.first) & 1u) types += (types.empty() ? "" : ", ") + t.second;
        out << ' ' << (f.usedBy == 0 ? std::string("all") : types) << " |";
      } else {
        out << ' '
            << (f.usedBy == 0 ? "both" : (f.usedBy >> SoBSplineDeformSurface::SHELL) & 1u ? "SHELL" : "PAPER")
            << " |";
      }
      out << '\n';
    }
    out << '\n';
  }
  return out.str();
}

}  // namespace bsdeform
