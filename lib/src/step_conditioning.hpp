// How far one solve with Newmark's step matrix can be trusted (newmark.hpp:
// NewmarkIntegrator::step_error_estimate), whichever path steps the model.
#pragma once

#include <Eigen/SparseCore>

namespace podid::internal {

/// The relative forward error (infinity norm) of solving S x = S e with a
/// sparse LDL^T factor of S = a0 M + a1 C + K, the largest over two probes e
/// of known answer: all ones, and a fixed pseudo-random vector in [-1, 1].
/// NaN when S has no such factor (the integrator's own checks report it).
double StepSolveErrorEstimate(const Eigen::SparseMatrix<double>& mass,
                              const Eigen::SparseMatrix<double>& damping,
                              const Eigen::SparseMatrix<double>& stiffness,
                              double a0,
                              double a1);

}  // namespace podid::internal
