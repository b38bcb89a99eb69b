#pragma once
// The ridge's cost of a coefficient, -log|W| (podid/wavelet/ridge.hpp), over a
// run of coefficients, and |W| itself (the scale screen, the float
// scalogram). A vectorisable logarithm (no libm call per coefficient) and
// square roots: on x86-64 with GCC built for x86-64-v4 (AVX-512), x86-64-v3
// (AVX2, FMA) and the baseline, the loader picking the one the CPU runs.

#include <Eigen/Core>
#include <complex>

namespace podid::wavelet::internal {

/// |W|^2 is floored at this (relative to a peak of about 1): far below any
/// coefficient that can matter, far above the subnormal range.
inline constexpr double kRidgeCostFloor = 1e-300;

/// 2^-e for the largest finite |re|, |im| of w's entries in [2^(e-1), 2^e)
/// (1 if there is none): scale w has parts below 1, so |scale w|^2 cannot
/// overflow, whatever the magnitude of w (a transform keeps W up to 2^961).
/// *all_finite (unless null): whether every entry of w is finite.
double UnitScale(const Eigen::Ref<const Eigen::MatrixXcd>& w, bool* all_finite = nullptr);

/// power[i] = |scale w[i]|^2 for i < n. Finite w only; scale: a power of 2
/// bringing the peak |W| near 1.
void RidgePower(const std::complex<double>* w, Eigen::Index n, double scale, double* power);

/// magnitude[i] = |w[i]| = sqrt(re^2 + im^2), correctly rounded, for i < n.
void Magnitudes(const std::complex<double>* w, Eigen::Index n, double* magnitude);

/// out[i] = float(scale |w[i]|) for i < n: Magnitudes' values times scale,
/// rounded once to float, in one pass.
void MagnitudesToFloat(const std::complex<double>* w, Eigen::Index n, double scale, float* out);

/// cost[i] = -0.5 ln(max(power[i], kRidgeCostFloor)) for i < n (cost == power
/// allowed), within 4 ulp of max(1, |ln|) (measured 1 ulp; test RidgeCost.*).
/// Finite power >= 0 only. Not monotone to the last bit: a larger power may
/// cost up to 8 ulp of max(1, |ln|) more (RidgeProgramme allows for it).
void RidgeCostOfPower(const double* power, Eigen::Index n, double* cost);

/// RidgePower then RidgeCostOfPower: the same bits as the two calls, so a
/// cost computed from powers later (RidgeProgramme::PushLastPowers) is this one.
void RidgeCost(const std::complex<double>* w, Eigen::Index n, double scale, double* out);

}  // namespace podid::wavelet::internal
