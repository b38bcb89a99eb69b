#pragma once
// A large banded model for the sparse-core tests and benchmarks (issue 11):
// a chain of n masses joined by springs, and the process's peak memory.
// Header-only, without GoogleTest, so bench/ can include it too.

#include <Eigen/SparseCore>
#include <fstream>
#include <string>
#include <vector>

#include "podid/core/beam_model.hpp"

namespace podid::testing {

/// A chain of n masses m (kg) joined by springs k (N/m), dof 0 tied to the
/// ground by k; Rayleigh C = alpha M + beta K. Banded (tridiagonal) K.
inline BeamModel Chain(int n, const std::vector<NonlinearitySpec>& nonlinearities) {
  constexpr double kMass_kg = 1e-3, kStiffness_N_per_m = 1e6, kAlpha_per_s = 1.0, kBeta_s = 1e-7;
  std::vector<Eigen::Triplet<double>> m, k;
  for (int i = 0; i < n; ++i) {
    m.emplace_back(i, i, kMass_kg);
    k.emplace_back(i, i, (i + 1 < n ? 2.0 : 1.0) * kStiffness_N_per_m);
    if (i + 1 < n) {
      k.emplace_back(i, i + 1, -kStiffness_N_per_m);
      k.emplace_back(i + 1, i, -kStiffness_N_per_m);
    }
  }
  Eigen::SparseMatrix<double> mass(n, n), stiffness(n, n);
  mass.setFromTriplets(m.begin(), m.end());
  stiffness.setFromTriplets(k.begin(), k.end());
  const Eigen::SparseMatrix<double> damping = kAlpha_per_s * mass + kBeta_s * stiffness;
  return BeamModel::FromMatrices(mass, stiffness, damping, nonlinearities);
}

/// Two cubic springs (k3 = 1e12 N/m^3) on dofs n / 2 and n - 2 of a Chain.
inline std::vector<NonlinearitySpec> TwoCubics(int n) {
  NonlinearitySpec a;
  a.type = NonlinearType::kCubic;
  a.node = n / 4 + 1;  // dof 2 (node - 1) = n / 2
  a.k3_N_per_m3 = 1e12;
  NonlinearitySpec b = a;
  b.node = n / 2;  // dof n - 2
  return {a, b};
}

/// Peak resident memory of this process (VmHWM), in bytes; -1 if unknown.
inline long long PeakRssBytes() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      long long kb = 0;
      status >> kb;
      return kb * 1024;
    }
    std::getline(status, key);
  }
  return -1;
}

}  // namespace podid::testing
