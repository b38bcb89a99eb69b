// The step matrix's conditioning probe (step_conditioning.hpp).
//
// A backward-stable solve can still be far off when S is ill-conditioned: a
// pinned beam whose last 0.01 m holds 998 of its 1000 elements (lengths
// 49,500x apart) solves S x = S 1 with a relative error of 2.4e-2, and its
// transient, every step such a solve, is 1e-2 off a long-double integration
// after 100 steps of 1e-4 s (docs/case-file.md). The static solve estimates
// its error by one more Newton step (beam_model.cpp); the time loop has no
// spare solve, so the estimate is made once, before it, on probes whose
// answer is known.
#include "step_conditioning.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace podid::internal {

double ProbeSolveError(const Eigen::SparseMatrix<double>& s,
                       const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& solve) {
  const Eigen::Index n = s.rows();
  if (n == 0) return 0.0;
  Eigen::VectorXd probe = Eigen::VectorXd::Ones(n);
  double worst = 0.0;
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      // A fixed sequence (the minimal standard LCG, written out so that every
      // platform draws the same numbers): signs and sizes that ones lack.
      std::uint64_t state = 20261129;
      for (Eigen::Index i = 0; i < n; ++i) {
        state = state * 48271 % 2147483647;
        probe[i] = 2.0 * static_cast<double>(state) / 2147483647.0 - 1.0;
      }
    }
    const Eigen::VectorXd solved = solve(s * probe);
    const double error =
        (solved - probe).lpNorm<Eigen::Infinity>() / probe.lpNorm<Eigen::Infinity>();
    if (!std::isfinite(error)) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, error);
  }
  return worst;
}

double StepSolveErrorEstimate(const Eigen::SparseMatrix<double>& mass,
                              const Eigen::SparseMatrix<double>& damping,
                              const Eigen::SparseMatrix<double>& stiffness,
                              double a0,
                              double a1) {
  if (mass.rows() == 0) return 0.0;
  Eigen::SparseMatrix<double> s = a0 * mass + a1 * damping + stiffness;
  s.makeCompressed();
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(s);
  if (factor.info() != Eigen::Success) return std::numeric_limits<double>::quiet_NaN();
  return ProbeSolveError(
      s, [&](const Eigen::VectorXd& rhs) -> Eigen::VectorXd { return factor.solve(rhs); });
}

}  // namespace podid::internal
