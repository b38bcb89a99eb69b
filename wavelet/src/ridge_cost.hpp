#pragma once
// The ridge's cost of a coefficient, -log|W| (podid/wavelet/ridge.hpp), over a
// run of coefficients. A vectorisable logarithm (no libm call per
// coefficient): on x86-64 with GCC built for x86-64-v4 (AVX-512), x86-64-v3
// (AVX2, FMA) and the baseline, the loader picking the one the CPU runs.

#include <Eigen/Core>
#include <complex>

namespace podid::wavelet::internal {

/// |W|^2 is floored at this (relative to a peak of about 1): far below any
/// coefficient that can matter, far above the subnormal range.
inline constexpr double kRidgeCostFloor = 1e-300;

/// out[i] = -0.5 ln(max(|scale w[i]|^2, kRidgeCostFloor)) for i < n, within
/// 4 ulp of max(1, |ln|) (measured 1 ulp; test RidgeCost.*). Finite w only;
/// scale: a power of 2 bringing the peak |W| near 1.
void RidgeCost(const std::complex<double>* w, Eigen::Index n, double scale, double* out);

}  // namespace podid::wavelet::internal
