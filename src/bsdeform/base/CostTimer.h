// SPDX-License-Identifier: MIT
#pragma once
/// @file CostTimer.h
/// A scope's wall time added to a counter of seconds (StepCosts.h, BarrierContactForce::Costs).

#include <chrono>

namespace bsdeform {

/// Adds the wall time of its scope to a counter of seconds (nothing when given null).
class CostTimer {
 public:
  explicit CostTimer(double* field) : m_field(field) {
    if (m_field) m_start = std::chrono::steady_clock::now();
  }
  ~CostTimer() {
    if (m_field) *m_field += std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
  }
  CostTimer(const CostTimer&) = delete;
  CostTimer& operator=(const CostTimer&) = delete;

 private:
  double* m_field;
  std::chrono::steady_clock::time_point m_start;
};

}  // namespace bsdeform
