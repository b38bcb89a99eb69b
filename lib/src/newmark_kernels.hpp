#pragma once
// The dense condensed integrator's per-step kernels (not installed), each in a
// portable version and an AVX2 one chosen at run time when the CPU has it
// (the build stays baseline x86-64; NewmarkOptions::cpu_dispatch = false
// forces the portable ones).

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
UpdateKernel SelectUpdateKernel(bool cpu_dispatch);

}  // namespace podid::internal
