// SPDX-License-Identifier: MIT
// The one Newton solver of backward Euler and the static solve (dynamics/NewtonMinimizer), on
// functions whose minimum is known: convergence with few factorisations (chord steps between), convergence
// where the potential's change is below its rounding (the line search then watches the
// gradient), and a singular tangent (a free body's rigid motion) shifted until it factorises.
#include <Eigen/SparseCore>
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <vector>

#include "bsdeform/dynamics/NewtonMinimizer.h"

using namespace bsdeform;

namespace {

// f(x) = offset + Σ ½ a (x - c)² + ¼ b (x - c)⁴ over every entry of an n x 3 net; c known.
struct Quartic {
  ControlNet c;
  double a = 2.0, b = 5.0, offset = 0.0;
  Eigen::SparseMatrix<double> K;
  ControlNet at;  // the last evaluated point
  explicit Quartic(Eigen::Index n) : c(ControlNet::Random(n, 3)) {}

  NewtonMinimizer::Problem problem() {
    NewtonMinimizer::Problem p;
    p.evaluate = [this](const ControlNet& x, NewtonPoint& pt) {
      at = x;
      const Eigen::ArrayXXd d = (x - c).array();
      pt.g = (a * d + b * d.cube()).matrix();
      pt.norm = pt.g.norm();
      const double f = (0.5 * a * d.square() + 0.25 * b * d.square().square()).sum();
      pt.value = offset + f;
      pt.valueScale = std::abs(offset) + f;
      pt.potential = true;
    };
    p.tangent = [this](HessianMode, double shift) -> const Eigen::SparseMatrix<double>& {
      const Eigen::Index n = at.size();
      K.resize(n, n);
      K.setZero();
      std::vector<Eigen::Triplet<double>> t;
      for (Eigen::Index i = 0; i < at.rows(); ++i)
        for (int k = 0; k < 3; ++k) {
          const double d = at(i, k) - c(i, k);
          t.emplace_back(3 * i + k, 3 * i + k, a + 3.0 * b * d * d + shift);
        }
      K.setFromTriplets(t.begin(), t.end());
      return K;
    };
    p.residualSmall = [](const NewtonPoint& pt) { return pt.norm == 0.0; };  // only the step decides
    return p;
  }
};


/// A step's potential per coordinate, ½ m (x - x̂)² + W(x) + q cos(x) with x̂ the same for
/// every coordinate: W = ¼ (x² - 1)² a double well (W'' = 3x² - 1 < 0 near 0), the energy, its
/// Hessian clamped at 0 by HessianMode::Projected and Definite; q cos(x) a load whose curvature
/// -q cos(x) only Definite clamps (a barrier's pair). The tangent records the modes asked for.
struct WellUnderLoad {
  double m, q;
  Eigen::Index n;
  ControlNet xhat, at;
  Eigen::SparseMatrix<double> K;
  std::vector<HessianMode> modes;
  WellUnderLoad(double mass, Eigen::Index points, double target, double load = 0.0)
      : m(mass), q(load), n(points), xhat(ControlNet::Constant(points, 3, target)) {}
  /// evaluate and tangent (the caller sets residualSmall); this object must outlive it
  NewtonMinimizer::Problem problem() {
    NewtonMinimizer::Problem p;
    p.evaluate = [this](const ControlNet& x, NewtonPoint& pt) {
      at = x;
      const Eigen::ArrayXXd d = (x - xhat).array(), a = x.array();
      pt.g = (m * d + a.cube() - a - q * a.sin()).matrix();
      pt.norm = pt.g.norm();
      pt.value = 0.5 * m * d.square().sum() + (0.25 * (a.square() - 1.0).square()).sum() + q * a.cos().sum();
      pt.valueScale = std::abs(pt.value) + 1.0;
      pt.potential = true;
    };
    p.tangent = [this](HessianMode mode, double shift) -> const Eigen::SparseMatrix<double>& {
      modes.push_back(mode);
      K.resize(3 * n, 3 * n);
      std::vector<Eigen::Triplet<double>> t;
      for (Eigen::Index i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
          double w = 3.0 * at(i, k) * at(i, k) - 1.0, l = -q * std::cos(at(i, k));
          if (mode != HessianMode::Exact) w = std::max(w, 0.0);
          if (mode == HessianMode::Definite) l = std::max(l, 0.0);
          t.emplace_back(int(3 * i + k), int(3 * i + k), w + l + shift);
        }
      K.setFromTriplets(t.begin(), t.end());
      return K;
    };
    return p;
  }
};
}  // namespace

TEST_CASE("NewtonMinimizer: converges to the known minimum with a few factorisations and chord steps", "[newton]") {
  Quartic q(40);
  ControlNet x = ControlNet::Zero(40, 3);
  NewtonPoint cur;
  const auto problem = q.problem();
  problem.evaluate(x, cur);
  NewtonMinimizer::Options o;
  o.updateTolerance = 1e-12;
  NewtonMinimizer m;
  const auto out = m.minimize(x, cur, problem, o);
  REQUIRE(out.converged);
  CHECK((x - q.c).cwiseAbs().maxCoeff() < 1e-12);
  // |c| <= 1: a handful of factorisations, kept while the updates at least halve with them
  CHECK(out.factorisations <= 4);
  CHECK(out.iterations <= 15);
}

TEST_CASE("NewtonMinimizer: without chord steps the step that confirms convergence keeps the last factorisation", "[newton]") {
  // a barrier's Newton (chordSteps false): a new factorisation every iteration, except the last,
  // whose direction the factorisation before it solves below half the tolerance
  Quartic q(40);
  for (Eigen::Index i = 0; i < q.c.rows(); ++i)  // a fixed minimum (not std::rand's state)
    for (int k = 0; k < 3; ++k) q.c(i, k) = std::sin(1.0 + 7.0 * double(i) + 3.0 * k);
  const auto problem = q.problem();
  NewtonMinimizer::Options o;
  o.updateTolerance = 1e-5;  // the last direction below 5e-6 on the factorisation before it
  o.chordSteps = false;
  auto run = [&](bool keep, ControlNet& x) {
    x = ControlNet::Zero(40, 3);
    NewtonPoint cur;
    problem.evaluate(x, cur);
    o.keptFactorNearMinimum = keep;
    NewtonMinimizer m;
    return m.minimize(x, cur, problem, o);
  };
  ControlNet full, kept;
  const auto a = run(false, full), b = run(true, kept);
  REQUIRE(a.converged);
  REQUIRE(b.converged);
  CHECK(a.factorisations == a.iterations);
  CHECK(b.iterations == a.iterations);
  CHECK(b.factorisations == b.iterations - 1);
  // the kept step is below the tolerance: the minimum is as near as the tolerance says
  CHECK((kept - q.c).cwiseAbs().maxCoeff() < o.updateTolerance);
  CHECK((full - q.c).cwiseAbs().maxCoeff() < o.updateTolerance);
}

TEST_CASE("NewtonMinimizer: the kept factorisation's short direction confirms the step and a longer one is dropped",
          "[newton]") {
  // f' = a d + b d³ per coordinate: from d = 10⁻³ one Newton step leaves about b d³ / a; the
  // step factorised there solves the next direction below half the tolerance (one factorisation
  // for the whole minimisation, where every iteration factorised before)
  Quartic q(30);
  for (Eigen::Index i = 0; i < q.c.rows(); ++i)
    for (int k = 0; k < 3; ++k) q.c(i, k) = std::cos(0.5 + 3.0 * double(i) + k);
  NewtonMinimizer::Problem problem = q.problem();
  std::vector<ControlNet> points;  // every point evaluated, in order
  const auto evaluate = problem.evaluate;
  problem.evaluate = [&](const ControlNet& x, NewtonPoint& pt) {
    points.push_back(x);
    evaluate(x, pt);
  };
  NewtonMinimizer::Options o;
  o.updateTolerance = 1e-5;
  o.chordSteps = false;
  auto run = [&](bool keep, const ControlNet& start, ControlNet& x, std::vector<ControlNet>& seen) {
    points.clear();
    x = start;
    NewtonPoint cur;
    problem.evaluate(x, cur);
    o.keptFactorNearMinimum = keep;
    NewtonMinimizer m;
    const auto out = m.minimize(x, cur, problem, o);
    seen = points;
    return out;
  };
  ControlNet x;
  std::vector<ControlNet> full, kept;
  SECTION("a start near the minimum") {
    const ControlNet start = q.c + ControlNet::Constant(30, 3, 1e-3);
    const auto a = run(false, start, x, full);
    const auto b = run(true, start, x, kept);
    REQUIRE(a.converged);
    REQUIRE(b.converged);
    CHECK(a.iterations == 2);
    CHECK(a.factorisations == 2);
    CHECK(b.iterations == 2);
    CHECK(b.factorisations == 1);
    CHECK((x - q.c).cwiseAbs().maxCoeff() < 1e-12);
  }
  SECTION("a start far from it: the directions above half the tolerance are dropped, Newton's iterates kept") {
    const ControlNet start = ControlNet::Zero(30, 3);
    const auto a = run(false, start, x, full);
    const auto b = run(true, start, x, kept);
    REQUIRE(a.converged);
    REQUIRE(b.converged);
    REQUIRE(a.iterations >= 4);
    CHECK(b.iterations == a.iterations);
    CHECK(b.factorisations == a.factorisations - 1);
    // every point up to the last iteration's is Newton's own, bit for bit
    REQUIRE(kept.size() == full.size());
    for (size_t i = 0; i + 1 < kept.size(); ++i) CHECK((kept[i] - full[i]).cwiseAbs().maxCoeff() == 0.0);
    CHECK((x - q.c).cwiseAbs().maxCoeff() < 0.5 * o.updateTolerance);
  }
}

TEST_CASE("NewtonMinimizer: no kept direction after a step on a projected tangent", "[newton]") {
  // keptFactorNearMinimum trusts the last factorisation only after a full step on the exact
  // tangent: after one on a projected matrix (the exact one refused here) a new one follows, even
  // where the projected matrix's direction would be short enough
  Quartic q(20);
  for (Eigen::Index i = 0; i < q.c.rows(); ++i)
    for (int k = 0; k < 3; ++k) q.c(i, k) = std::sin(0.3 + 2.0 * double(i) + k);
  NewtonMinimizer::Problem problem = q.problem();
  NewtonMinimizer::Options o;
  o.updateTolerance = 1e-5;
  o.chordSteps = false;
  o.keptFactorNearMinimum = true;
  o.maxIterations = 200;
  const auto tangent = problem.tangent;
  Eigen::SparseMatrix<double> negative;
  problem.tangent = [&](HessianMode mode, double shift) -> const Eigen::SparseMatrix<double>& {
    if (mode != HessianMode::Exact) return tangent(mode, shift);
    negative = -tangent(mode, shift);  // not positive definite: the projected one follows
    return negative;
  };
  ControlNet x = q.c + ControlNet::Constant(20, 3, 1e-3);  // near the minimum: a kept direction would do
  NewtonPoint cur;
  problem.evaluate(x, cur);
  NewtonMinimizer m;
  const auto out = m.minimize(x, cur, problem, o);
  REQUIRE(out.converged);
  CHECK(out.iterations >= 2);
  CHECK(out.factorisations == out.iterations);
  CHECK((x - q.c).cwiseAbs().maxCoeff() < 1e-4);
}

TEST_CASE("NewtonMinimizer: L-BFGS on its own start factorises once whether chord steps are on or off", "[newton]") {
  // with a barrier backward Euler turns chord steps off; L-BFGS there starts from the first
  // iterate's tangent, factorised once, whatever keptFactorNearMinimum says
  Quartic q(40);
  for (Eigen::Index i = 0; i < q.c.rows(); ++i)
    for (int k = 0; k < 3; ++k) q.c(i, k) = 0.5 * std::cos(2.0 + 5.0 * double(i) + k);
  const auto problem = q.problem();
  for (const bool chords : {true, false}) {
    CAPTURE(chords);
    NewtonMinimizer::Options o;
    o.updateTolerance = 1e-9;
    o.quasiNewton = true;
    o.maxIterations = 300;
    o.chordSteps = chords;
    o.keptFactorNearMinimum = !chords;
    ControlNet x = ControlNet::Zero(40, 3);
    NewtonPoint cur;
    problem.evaluate(x, cur);
    NewtonMinimizer m;
    const auto out = m.minimize(x, cur, problem, o);
    REQUIRE(out.converged);
    CHECK(out.iterations > 3);
    CHECK(out.factorisations == 1);
    CHECK((x - q.c).cwiseAbs().maxCoeff() < 1e-7);
  }
}

TEST_CASE("NewtonMinimizer: an indefinite exact tangent takes more of the mass before the projected one",
          "[newton]") {
  // a step's potential ½ m (x - x̂)² + W(x) per coordinate, W = ¼ (x² - 1)² a double well
  // (W'' = 3x² - 1 < 0 near 0), m = 0.7: at x = 0 the exact tangent 0.7 - 1 is not positive
  // definite, 1.25 m - 1 is not either, 1.25² m - 1 = 0.094 is (the second retry); the projected
  // one (W'' clamped at 0) is what the dynamics fall back to otherwise
  constexpr double m = 0.7;
  constexpr Eigen::Index n = 6;
  WellUnderLoad well(m, n, 0.05);  // no load
  Eigen::SparseMatrix<double>& K = well.K;
  const std::vector<HessianMode>& modes = well.modes;
  NewtonMinimizer::Problem p = well.problem();
  p.residualSmall = [](const NewtonPoint& pt) { return pt.norm == 0.0; };
  NewtonMinimizer::Options o;
  o.updateTolerance = 1e-12;
  o.shift = m;
  o.chordSteps = false;
  auto run = [&](bool shifted) {
    o.massRetries = shifted ? 5 : 0;
    NewtonMinimizer::Problem q = p;
    if (shifted) {
      q.shiftTangent = [&](double extra) -> const Eigen::SparseMatrix<double>& {
        for (int i = 0; i < K.rows(); ++i) K.coeffRef(i, i) += extra;
        return K;
      };
    }
    ControlNet x = ControlNet::Zero(n, 3);
    NewtonPoint cur;
    q.evaluate(x, cur);
    well.modes.clear();
    NewtonMinimizer minimizer;
    const auto out = minimizer.minimize(x, cur, q, o);
    REQUIRE(out.converged);
    // a minimum of the step's potential: the gradient zero, the exact tangent positive
    CHECK(cur.g.cwiseAbs().maxCoeff() < 1e-10);
    CHECK((m + 3.0 * x.array().square() - 1.0).minCoeff() > 0.0);
    return x;
  };
  auto projectedTangents = [&] {
    return std::count_if(modes.begin(), modes.end(), [](HessianMode m) { return m != HessianMode::Exact; });
  };
  const ControlNet projected = run(false);
  CHECK(projectedTangents() > 0);
  const ControlNet shifted = run(true);
  CHECK(projectedTangents() == 0);
  CHECK((shifted - projected).cwiseAbs().maxCoeff() < 1e-10);  // the same minimum
}

TEST_CASE("NewtonMinimizer: the projected tangent keeps the loads' Jacobians exact while more of the mass "
          "makes it definite",
          "[newton]") {
  // per coordinate ½ m (x - x̂)² + W(x) + q cos(x): W = ¼ (x² - 1)² the energy (its Hessian
  // projected in both Projected and Definite), q cos(x) a load whose curvature -q cos(x) only
  // Definite clamps at 0 (a barrier's pair). At x = 0 the tangent with the mass multiple s is
  // s + W'' - q, W'' = -1 (0 projected): with q = 2 m the projected tangent fails at s = m and
  // factorises at 4 m with the load exact; with q = 40 m it needs more than 16 m, and after three
  // attempts with the load exact (m, 4 m, 16 m) the load is projected too.
  constexpr double m = 0.5;
  constexpr Eigen::Index n = 4;
  WellUnderLoad well(m, n, 0.02);
  const std::vector<HessianMode>& modes = well.modes;
  NewtonMinimizer::Problem p = well.problem();
  p.residualSmall = [](const NewtonPoint& pt) { return pt.norm <= 1e-12; };
  NewtonMinimizer::Options o;
  o.updateTolerance = 1e-13;
  o.shift = m;
  o.chordSteps = false;
  auto run = [&](double load) {
    well.q = load;
    ControlNet x = ControlNet::Zero(n, 3);
    NewtonPoint cur;
    p.evaluate(x, cur);
    well.modes.clear();
    NewtonMinimizer minimizer;
    const auto out = minimizer.minimize(x, cur, p, o);
    CAPTURE(load, out.failure);
    REQUIRE(out.converged);
    CHECK(cur.g.cwiseAbs().maxCoeff() < 1e-10);  // a stationary point of the whole potential
  };
  run(2.0 * m);
  REQUIRE(modes.size() >= 3);
  CHECK(modes[0] == HessianMode::Exact);
  CHECK(modes[1] == HessianMode::Projected);
  CHECK(modes[2] == HessianMode::Projected);  // at 4 m, the load still exact
  CHECK(std::count(modes.begin(), modes.end(), HessianMode::Definite) == 0);
  run(40.0 * m);
  REQUIRE(modes.size() >= 5);
  const std::vector<HessianMode> first(modes.begin(), modes.begin() + 5);
  CHECK(first == std::vector<HessianMode>{HessianMode::Exact, HessianMode::Projected, HessianMode::Projected,
                                          HessianMode::Projected, HessianMode::Definite});
}

TEST_CASE("NewtonMinimizer: converges where the potential's change is below its rounding", "[newton]") {
  // a large constant beside f: near the minimum every change of the value is rounding, and an
  // Armijo search on the value alone refuses every step (the iteration stalls)
  Quartic q(40);
  q.offset = 1e9;
  ControlNet x = ControlNet::Zero(40, 3);
  NewtonPoint cur;
  const auto problem = q.problem();
  problem.evaluate(x, cur);
  NewtonMinimizer::Options o;
  o.updateTolerance = 1e-12;
  NewtonMinimizer m;
  const auto out = m.minimize(x, cur, problem, o);
  CAPTURE(out.failure);
  REQUIRE(out.converged);
  CHECK((x - q.c).cwiseAbs().maxCoeff() < 1e-12);
}

TEST_CASE("NewtonMinimizer: a singular tangent (a free chain) is shifted until it factorises and converges",
          "[newton]") {
  // f = ½ Σ |x_{i+1} - x_i|² - Σ b_i·x_i with Σ b_i = 0: a free chain under balanced loads,
  // singular along translations; the minimisers differ by a translation
  const Eigen::Index n = 30;
  ControlNet b = ControlNet::Random(n, 3);
  b.rowwise() -= b.colwise().mean();
  Eigen::SparseMatrix<double> K;
  std::vector<Eigen::Triplet<double>> lap;
  for (int k = 0; k < 3; ++k)
    for (Eigen::Index i = 0; i + 1 < n; ++i) {
      const Eigen::Index p = 3 * i + k, q = 3 * (i + 1) + k;  // ControlNet is row-major
      lap.emplace_back(p, p, 1.0);
      lap.emplace_back(q, q, 1.0);
      lap.emplace_back(p, q, -1.0);
      lap.emplace_back(q, p, -1.0);
    }
  Eigen::SparseMatrix<double> L(3 * n, 3 * n);
  L.setFromTriplets(lap.begin(), lap.end());
  auto apply = [&](const ControlNet& x) {
    Eigen::Map<const Eigen::VectorXd> v(x.data(), x.size());
    const Eigen::VectorXd y = L * v;
    return ControlNet(Eigen::Map<const ControlNet>(y.data(), n, 3));
  };
  NewtonMinimizer::Problem p;
  p.evaluate = [&](const ControlNet& x, NewtonPoint& pt) {
    const ControlNet Lx = apply(x);
    pt.g = Lx - b;
    pt.norm = pt.g.norm();
    pt.value = 0.5 * (x.array() * Lx.array()).sum() - (b.array() * x.array()).sum();
    pt.valueScale = 0.5 * (x.array() * Lx.array()).abs().sum() + (b.array() * x.array()).abs().sum();
    pt.potential = true;
  };
  int factorised = 0;
  p.tangent = [&](HessianMode, double shift) -> const Eigen::SparseMatrix<double>& {
    ++factorised;
    K = L;
    for (Eigen::Index i = 0; i < K.rows(); ++i) K.coeffRef(i, i) += shift;
    return K;
  };
  p.residualSmall = [&](const NewtonPoint& pt) { return pt.norm <= 1e-10 * b.norm(); };
  NewtonMinimizer::Options o;
  o.maxIterations = 200;
  o.updateTolerance = 1e-14;
  o.firstExtraShift = 1e-6;
  o.shiftAttempts = 40;
  o.rememberShift = true;
  ControlNet x = ControlNet::Zero(n, 3);
  NewtonPoint cur;
  p.evaluate(x, cur);
  NewtonMinimizer m;
  const auto out = m.minimize(x, cur, p, o);
  CAPTURE(out.failure, out.iterations);
  REQUIRE(out.converged);
  CHECK(cur.norm <= 1e-10 * b.norm());
  CHECK(factorised >= 2);  // the exact (singular) tangent was refused, a shifted one made
}
