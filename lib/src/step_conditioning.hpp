// How far one solve with Newmark's step matrix can be trusted (newmark.hpp:
// NewmarkIntegrator::step_error_estimate), whichever path steps the model.
#pragma once

#include <Eigen/SparseCore>
#include <functional>

namespace podid::internal {

/// The relative forward error (infinity norm) of x = solve(S e) for two
/// probes e of known answer, all ones and a fixed pseudo-random vector in
/// [-1, 1]: the larger of the two (0 for an empty S, +inf if x is not finite).
double ProbeSolveError(const Eigen::SparseMatrix<double>& s,
                       const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& solve);

/// ProbeSolveError of S = a0 M + a1 C + K with a sparse LDL^T factor of its
/// own (AMD ordering), or NaN when S has none (the integrator's own checks
/// report it). For the dense paths; the sparse one probes its factor of S_bb.
double StepSolveErrorEstimate(const Eigen::SparseMatrix<double>& mass,
                              const Eigen::SparseMatrix<double>& damping,
                              const Eigen::SparseMatrix<double>& stiffness,
                              double a0,
                              double a1);

}  // namespace podid::internal
