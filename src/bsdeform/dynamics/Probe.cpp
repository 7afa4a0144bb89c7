// SPDX-License-Identifier: MIT
#include "bsdeform/dynamics/Probe.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "bsdeform/base/NumberText.h"
#include "bsdeform/dynamics/Simulation.h"

namespace bsdeform {

ProbeSample probe(const SplineSpace& space, const ControlNet& net, const ControlNet& rest, double u, double v) {
  for (const auto& [value, name] : {std::make_pair(u, "u"), std::make_pair(v, "v")})
    if (!(value >= 0.0 && value <= 1.0))
      throw std::invalid_argument(std::string("probe: ") + name + " must be in [0, 1], got " + numberText(value));
  ProbeSample p;
  p.point = space.evaluate(net, u, v, 0).position;
  p.displacement = p.point - space.evaluate(rest, u, v, 0).position;
  return p;
}

ProbeSample probe(const Simulation& sim, double u, double v) { return probe(sim, sim.current(), u, v); }

ProbeSample probe(const Simulation& sim, const ControlNet& net, double u, double v) {
  return probe(sim.space(), net, sim.rest(), u, v);
}

}  // namespace bsdeform
