// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/ArcLength.h"

#include <Eigen/SparseLU>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "bsdeform/base/NumberText.h"

namespace bsdeform {

namespace {

// K factorised by LU with partial pivoting (indefinite beyond a limit point); the pattern
// analysed once.
class Factor {
 public:
  bool factor(Eigen::SparseMatrix<double> K, bool lowerOnly) {
    if (lowerOnly) {
      Eigen::SparseMatrix<double> upper = K.transpose();
      upper.diagonal().setZero();
      K += upper;
    }
    K.makeCompressed();
    if (!m_analysed) {
      m_lu.analyzePattern(K);
      m_analysed = true;
    }
    m_lu.factorize(K);
    return m_lu.info() == Eigen::Success;
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) { return m_lu.solve(b); }

 private:
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> m_lu;
  bool m_analysed = false;
};

}  // namespace

std::vector<ArcLengthPoint> arcLengthPath(const Eigen::VectorXd& x0, const ArcLengthProblem& problem,
                                          const ArcLengthOptions& options,
                                          const std::function<void(const ArcLengthPoint&)>& each) {
  if (!(options.maxLoad > 0.0)) throw std::invalid_argument("arc length: the largest load factor must be > 0");
  if (options.maxSteps < 1) throw std::invalid_argument("arc length: the number of steps must be >= 1");
  if (!(options.minArcLength >= 0.0)) throw std::invalid_argument("arc length: the smallest arc length must be >= 0");
  std::vector<ArcLengthPoint> path;
  Factor lu;
  Eigen::VectorXd x = x0, g, F;
  double lambda = 0.0;
  Eigen::VectorXd lastIncrement;  // the last converged step's Δx (empty before the first)
  double lastLoadIncrement = 0.0;
  double dl = options.arcLength, firstLength = options.arcLength;
  // a Newton correction below this length at x counts as converged (the relative residual has a
  // rounding floor where large internal forces cancel; a correction's length does not)
  auto updateToleranceAt = [&](const Eigen::VectorXd& at) {
    return std::max(options.updateTolerance, problem.updateTolerance ? problem.updateTolerance(at) : 0.0);
  };
  auto relative = [](const Eigen::VectorXd& gi, const Eigen::VectorXd& Fi, double li) {
    const Eigen::VectorXd R = gi - li * Fi;
    return R.norm() / (gi.norm() + std::abs(li) * Fi.norm() + 1e-300);
  };
  for (int step = 1; step <= options.maxSteps && lambda < options.maxLoad; ++step) {
    // predictor: the tangent at the last equilibrium
    problem.evaluate(x, g, F);
    if (!lu.factor(problem.tangent(x), problem.lowerOnly))
      throw std::runtime_error("arc length: the tangent at load factor " + numberText(lambda) +
                               " cannot be factorised (a free body, or a structure nothing holds)");
    const Eigen::VectorXd dt = lu.solve(F);
    if (!dt.allFinite() || dt.norm() == 0.0)
      throw std::runtime_error("arc length: no response to the load at load factor " + numberText(lambda));
    if (dl == 0.0) dl = firstLength = dt.norm() * options.maxLoad / options.maxSteps;
    // along the last step's direction (the sign of the tangent's load factor flips at a limit
    // point; the displacement path goes on)
    double sign = 1.0;
    if (lastIncrement.size()) sign = dt.dot(lastIncrement) < 0.0 ? -1.0 : 1.0;
    else if (lastLoadIncrement < 0.0) sign = -1.0;
    // the shortest step: one below it moves by no more than the corrector's own tolerances
    // and would let the path creep on without moving (a stall, e.g. where the residual has a
    // rounding floor); it ends the path instead
    const double minLength = options.minArcLength > 0.0 ? options.minArcLength : 1e-4 * firstLength;
    bool converged = false;
    ArcLengthPoint point;
    for (int cut = 0; !converged; ++cut, dl *= 0.5) {
      if (cut > options.maxCuts)
        throw std::runtime_error("arc length: step " + std::to_string(step) + " from load factor " +
                                 numberText(lambda) + " did not converge even at 2^-" +
                                 std::to_string(options.maxCuts) + " of the arc length (" +
                                 std::to_string(path.size()) + " points found)");
      if (dl < minLength)
        throw std::runtime_error("arc length: the path stalls at load factor " + numberText(lambda) + ": step " +
                                 std::to_string(step) + " was cut to an arc length of " + numberText(dl) +
                                 ", below the smallest, " + numberText(minLength) +
                                 ", without converging (" + std::to_string(path.size()) +
                                 " points found; a looser tolerance or update tolerance may pass it)");
      double dLambda = sign * dl / dt.norm();
      Eigen::VectorXd dx = dLambda * dt;
      Eigen::VectorXd xi = x + dx;
      double li = lambda + dLambda;
      int it = 0;
      for (; it <= options.maxIterations; ++it) {
        problem.evaluate(xi, g, F);
        if (!g.allFinite()) break;
        const double r = relative(g, F, li);
        if (r <= options.tolerance) {
          converged = true;
          point.residual = r;
          break;
        }
        if (it == options.maxIterations) break;
        if (!lu.factor(problem.tangent(xi), problem.lowerOnly)) break;
        const Eigen::VectorXd dR = lu.solve(-(g - li * F)), dF = lu.solve(F);
        if (!dR.allFinite() || !dF.allFinite()) break;
        // |dx + dR + s dF|² = dl²
        const Eigen::VectorXd base = dx + dR;
        const double a = dF.squaredNorm(), b = 2.0 * dF.dot(base), c = base.squaredNorm() - dl * dl;
        const double disc = b * b - 4.0 * a * c;
        if (!(a > 0.0) || disc < 0.0) break;  // no point at this distance: a shorter step
        const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
        const double s1 = q / a, s2 = q != 0.0 ? c / q : s1;
        // the root whose new increment turns least from the increment so far
        const Eigen::VectorXd n1 = base + s1 * dF, n2 = base + s2 * dF;
        const double s = n1.dot(dx) >= n2.dot(dx) ? s1 : s2;
        const Eigen::VectorXd correction = dR + s * dF;
        dx += correction;
        li += s;
        xi = x + dx;
        // or converged when the correction is below the update tolerance: the relative residual
        // has a rounding floor where large internal forces cancel (it then stays above the
        // tolerance however close the point is), a Newton correction's length does not
        const double updateTolerance = updateToleranceAt(xi);
        if (updateTolerance > 0.0 && correction.cwiseAbs().maxCoeff() <= updateTolerance) {
          problem.evaluate(xi, g, F);
          if (g.allFinite()) {
            converged = true;
            point.residual = relative(g, F, li);
          }
          ++it;
          break;
        }
      }
      if (converged && lambda < options.maxLoad && li > options.maxLoad) {
        // the path crosses the largest load factor going up: it ends at exactly that load, the
        // equilibrium there found by Newton at fixed load from the straight line between the two
        // points (kept past it when that does not converge, e.g. right at a limit point)
        Eigen::VectorXd xf = x + ((options.maxLoad - lambda) / (li - lambda)) * dx;
        bool reached = false;
        int itf = 0;
        double rf = 0.0;
        for (; itf <= options.maxIterations; ++itf) {
          problem.evaluate(xf, g, F);
          if (!g.allFinite()) break;
          rf = relative(g, F, options.maxLoad);
          if (rf <= options.tolerance) {
            reached = true;
            break;
          }
          if (itf == options.maxIterations || !lu.factor(problem.tangent(xf), problem.lowerOnly)) break;
          const Eigen::VectorXd d = lu.solve(-(g - options.maxLoad * F));
          if (!d.allFinite()) break;
          xf += d;
          const double updateTolerance = updateToleranceAt(xf);
          if (updateTolerance > 0.0 && d.cwiseAbs().maxCoeff() <= updateTolerance) {
            problem.evaluate(xf, g, F);
            if (g.allFinite()) {
              reached = true;
              rf = relative(g, F, options.maxLoad);
            }
            ++itf;
            break;
          }
        }
        if (reached) {
          dx = xf - x;
          xi = xf;
          li = options.maxLoad;
          point.residual = rf;
          it += itf;
        }
      }
      if (converged) {
        lastIncrement = dx;
        lastLoadIncrement = li - lambda;
        x = xi;
        lambda = li;
        point.loadFactor = lambda;
        point.x = x;
        point.iterations = it;
        // the next arc length aims at 4 iterations (Crisfield's Δl sqrt(I_d / I), between half
        // and twice this one, at most maxArcLength or else 1000 times the first, at least the
        // shortest: only a cut goes below it)
        dl = std::max(minLength, std::min(dl * std::clamp(std::sqrt(4.0 / std::max(it, 1)), 0.5, 2.0),
                                          options.maxArcLength > 0.0 ? options.maxArcLength : 1000.0 * firstLength));
        break;
      }
    }
    path.push_back(point);
    if (each) each(path.back());
  }
  return path;
}

}  // namespace bsdeform
