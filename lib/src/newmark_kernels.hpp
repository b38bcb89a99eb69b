#pragma once
// The dense condensed integrator's per-step kernels (not installed), each in a
// portable version and an AVX2 one chosen at run time when the CPU has it
// (the build stays baseline x86-64; NewmarkOptions::cpu_dispatch = false
// forces the portable ones).

#include <algorithm>
#include <cmath>

#include "podid/core/newmark.hpp"

namespace podid::internal {

/// out = A u for a small column-major A (rows x cols, rows <= kDenseDofLimit).
using MultiplyKernel = void (*)(const double* a, int rows, int cols, const double* u, double* out);

/// One step's end on the dense condensed path (n dofs, z = [x; x'; x''] of the
/// last good step, dim 3 n, u dim 2 n):
///  1. x_new = y - h x_a when h is not null (eq. 28 with one nonlinear dof:
///     y = S_b^-1 rhs_b with y[0] = x_a, h[0] = 0), else x_new is the input;
///  2. false, z and u untouched, when some |x_new| exceeds max_displacement
///     or is not finite;
///  3. else the Newmark update z <- [x_new; x'_new; x''_new] and the next
///     step's u = [a0 x + a2 x' + a3 x''; a1 x + a4 x' + a5 x''] of it.
/// Every version does the same operations in the same order per dof (no
/// fused multiply-add): all give the same bits.
using UpdateKernel = bool (*)(const NewmarkCoefficients& c, int n, const double* y, const double* h,
                              double x_a, double* x_new, double* z, double* u);

MultiplyKernel SelectMultiplyKernel(bool cpu_dispatch);

/// eq. 29 for one nonlinear dof: R(x) = shat x - bhat - f(x, v(x)) with the
/// velocity v(x) = a1 (x - x_n) + v0 that the Newmark relations imply, by
/// Newton from *x (in: the start, out: the solution). Converged when |R| <=
/// tolerance max(|shat x|, |bhat|, |f|) (*residual = 0); false with the
/// relative residual when R is not finite or max_iterations pass. `forces`
/// is a NonlinearForces (EvaluateScalar); shared by the dense and modal steps.
template <class Forces>
inline bool SolveScalarNewton(const Forces& forces, double shat, double bhat, double a1, double x_n,
                              double v0, double tolerance, int max_iterations, double* x,
                              int* iterations, double* residual) {
  double xi = *x;
  int it = 0;
  for (;; ++it) {
    double f = 0.0, k = 0.0, c = 0.0;
    forces.EvaluateScalar(xi, a1 * (xi - x_n) + v0, &f, &k, &c);
    const double sx = shat * xi;
    const double scale = std::max({std::abs(sx), std::abs(bhat), std::abs(f), 1e-300});
    const double r = sx - bhat - f;
    // |r| <= tol scale: the relative residual test without a division on
    // the critical path; a non-finite r fails it and ends the step.
    if (std::abs(r) <= tolerance * scale) break;
    if (!std::isfinite(r) || it == max_iterations) {
      *iterations = it;
      *residual = std::abs(r) / scale;
      return false;
    }
    xi -= r / (shat + k + a1 * c);
  }
  *iterations = it;
  *residual = 0.0;
  *x = xi;
  return true;
}
UpdateKernel SelectUpdateKernel(bool cpu_dispatch);

/// A step's Newton count in the summary (its total, and its worst step and
/// when) and, if the step failed, why and when: false then, and the loop
/// ends. Shared by the dense, modal and one-dof loops.
inline bool CountStep(bool ok, int iterations, double residual, int step, double dt,
                      SimulationSummary* summary) {
  summary->newton_iterations += iterations;
  if (iterations > summary->max_step_iterations) {
    summary->max_step_iterations = iterations;
    summary->worst_step_time_s = step * dt;
  }
  if (ok) return true;
  summary->termination = std::isfinite(residual) ? SimulationTermination::kNewtonFailed
                                                 : SimulationTermination::kNonFinite;
  summary->failure_time_s = step * dt;
  summary->failure_residual = residual;
  return false;
}

}  // namespace podid::internal
