// The wavelet's extent in time, shared by CwtTransform, the band-limited
// blocks and the streamed ridge: its support's radius, the even extension
// that reflect padding reads, and the cone of influence's edge.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <numbers>

namespace podid::wavelet::internal {

// Time-domain half-width of the wavelet at scale s, in units of s: Morlet's
// Gaussian envelope falls below `tolerance` beyond 2 sigma_t sqrt(ln(1 /
// tolerance)) = sqrt(2 ln(1 / tolerance)); a Morse envelope is only nearly
// Gaussian, so it gets 1.5 times its own.
inline double SupportRadius(double time_spread, bool morse, double tolerance) {
  return (morse ? 1.5 : 1.0) * 2.0 * time_spread * std::sqrt(std::log(1.0 / tolerance));
}

// The even extension's index: m mirrored at 0 and n - 1 (period 2n - 2).
inline Eigen::Index Mirror(Eigen::Index m, Eigen::Index n) {
  const Eigen::Index period = 2 * n - 2;
  m %= period;
  if (m < 0) m += period;
  return m < n ? m : period - m;
}

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
