#pragma once
// Helpers shared by the time-series readers (not installed).

#include <cmath>

#include "podid/core/io.hpp"

namespace podid::internal {

/// True when `step` equals the reference step `h` within the tolerance of
/// io.hpp (kTimeStepRelativeTolerance, plus the rounding of %.12e at time t).
inline bool IsUniformStep(double step, double h, double t) {
  return std::abs(step - h) <= kTimeStepRelativeTolerance * h + 2e-12 * std::abs(t);
}

}  // namespace podid::internal
