// SPDX-License-Identifier: MIT
#pragma once
/// @file SceneRunner.h
/// Steps every SoBSplineDeformSurface of a scene to a common simulated time: the one place of
/// the rule that bsdeform-run, Python (bsdeform.run) and the viewer's Step share.
///
/// The rule: each surface takes whole steps of its own timeStep while its time plus half a step
/// is at most the time asked for, so surfaces with different time steps stay within half a
/// step of each other and of that time. While a runner lives, it alone drives its surfaces:
/// their realTime sensors are off (SoBSplineDeformSurface's clock), and nothing is written into
/// their fields' authored values (`on`, `speed`).
///
/// With Clock::Simulated the runner also drives Coin's realTime: the real-time sensor is
/// switched off and realTime follows the simulated time, so engines in the scene
/// (ElapsedTime ramps, TimeCounter...) animate in step with the surfaces, deterministically.
///
/// \code
/// bsdeform::SceneRunner runner(root);            // finds the surfaces, gives each its scene
/// for (int k = 1; k <= 40; ++k) runner.advanceTo(runner.startTime() + k * runner.timeStep());
/// \endcode

#include <string>
#include <vector>

class SoNode;
class SoBSplineDeformSurface;
class SoSFTime;

namespace bsdeform {

/// Coin's global realTime field: what every surface (and engine) follows, and what a driver
/// sets (SceneRunner, the viewer's clock, bsdeform-run).
SoSFTime* realTimeField();

class SceneRunner {
 public:
  enum class Clock {
    Simulated,  ///< realTime follows the simulated time (a runner, a script, a test)
    Untouched   ///< realTime is someone else's (the viewer's Step while its clock is paused)
  };
  /// Holds every distinct surface under `root` (sceneSurfaces()) and tells each the scene.
  explicit SceneRunner(SoNode* root, Clock clock = Clock::Simulated);
  /// Gives the surfaces their realTime sensors back.
  ~SceneRunner();
  SceneRunner(const SceneRunner&) = delete;
  SceneRunner& operator=(const SceneRunner&) = delete;

  const std::vector<SoBSplineDeformSurface*>& surfaces() const { return m_surfaces; }
  /// The smallest timeStep of the surfaces (their models built); 0 without surfaces.
  double timeStep() const;
  /// The smallest simulated time of the surfaces when the runner was made (a resumed scene
  /// goes on from its time).
  double startTime() const { return m_start; }
  /// The last time advanceTo() reached (startTime() before).
  double time() const { return m_time; }

  /// Sets realTime to `t` (Clock::Simulated), then steps each surface by the rule above.
  /// A surface whose step fails stops there (its problem() says why); the others go on.
  /// Returns false when a surface has failed (now or before).
  bool advanceTo(double t);
  /// advanceTo(time() + timeStep()).
  bool step();
  /// The surfaces whose simulation stopped, in scene order.
  std::vector<SoBSplineDeformSurface*> failed() const;

 private:
  Clock m_clock;
  std::vector<SoBSplineDeformSurface*> m_surfaces;  ///< ref'ed
  double m_start = 0.0, m_time = 0.0;
};

}  // namespace bsdeform
