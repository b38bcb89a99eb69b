// The cone of influence's edge, shared by CwtTransform and the streamed ridge.
#pragma once

#include <limits>
#include <numbers>

namespace podid::wavelet::internal {

// The lowest frequency (Hz) whose coefficient at edge_s from the nearer end
// of the record lies inside the cone: coi_factor times the e-folding time
// 2 sigma_t s reaches the end, s = kappa / (2 pi f). coi_factor 0 means no
// cone at all, the end samples included (where 0 / 0 would mark them outside).
inline double ConeFrequency_Hz(double coi_factor, double kappa, double time_spread, double edge_s) {
  if (coi_factor == 0.0) return 0.0;
  if (!(edge_s > 0.0)) return std::numeric_limits<double>::infinity();
  return coi_factor * kappa * 2.0 * time_spread / (2.0 * std::numbers::pi * edge_s);
}

}  // namespace podid::wavelet::internal
