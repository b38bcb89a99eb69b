#pragma once
// exp(2 pi i t / P) in long double: the references of the full-rate CWT's
// tests (direct DFTs and kernels summed with the angle reduced exactly).

#include <Eigen/Core>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

namespace podid::testing {

/// exp(2 pi i t / P), t = 0 .. P - 1.
inline std::vector<std::complex<long double>> RootsOfUnity(Eigen::Index p) {
  std::vector<std::complex<long double>> w(static_cast<std::size_t>(p));
  const long double step = 2.0L * std::numbers::pi_v<long double> / static_cast<long double>(p);
  for (Eigen::Index t = 0; t < p; ++t) {
    w[static_cast<std::size_t>(t)] = {std::cos(step * t), std::sin(step * t)};
  }
  return w;
}

}  // namespace podid::testing
