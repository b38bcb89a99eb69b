#pragma once
// The checks every transform applies to its input, with one set of messages
// (CwtTransform::Compute, WhiteNoiseMagnitude and the streamed ridge).

#include <Eigen/Core>
#include <cmath>

#include "podid/core/error.hpp"
#include "podid/core/time_series.hpp"
#include "podid/wavelet/cwt.hpp"

namespace podid::wavelet::internal {

// Steps are kMinStep_s .. kMaxStep_s (cwt.hpp). The energy normalisation
// multiplies W by sqrt(s). The scales lie between about step_s (Nyquist) and
// kappa / (2 pi kMinFrequencyOverRate) step_s < 2^67 step_s (the lowest
// frequency's bound), so within 2^-50 .. 2^117 s sqrt(s) stays within
// 2^-26 .. 2^58.5: the headroom the bounds below are chosen for. A step of
// 1e-200 s gave float outputs of 0 in every cell, 1e60 s gave inf, and so
// did 1e-300 Hz (bin 0 is inside every Morlet band: a scale of 1e300 s).
static_assert(kMinStep_s >= 0x1p-50 && kMaxStep_s <= 0x1p50);

/// The lowest frequency's bound, times the sampling rate: far below any use
/// (a period of 10^20 samples), and what keeps sqrt(s) within 2^58.5 above.
inline constexpr double kMinFrequencyOverRate = 1e-20;

/// Every transform scales its input by 2^-e to a peak in [1, 2); the
/// coefficients are returned in signal units when |e| <= this: |W| <= 4
/// sqrt(s) peak|x| <= 2^(961 + 2 + 58.5) then stays from overflow, and the
/// band's 1e-12 tails (2^-960-40-26) above the subnormals' precision loss at
/// any accepted step but the smallest ones (CwtTransform, the streamed ridge).
inline constexpr int kMaxUnscaledExponent = 960;
/// The same for single-precision output (float's range is 2^-126 .. 2^128):
/// within 2^+-32 of 1, |W| <= 2^(33 + 2 + 58.5) keeps 2^34 of headroom at the
/// largest scale, and the 1e-12 tails (2^-32-40-26 at the smallest) stay
/// 2^28 above the subnormals; beyond, the float values are in units of
/// coefficient_scale instead of overflowing to inf or flushing to 0 (a tone
/// of amplitude 1e40 or 1e-100).
inline constexpr int kMaxUnscaledFloatExponent = 32;

/// e such that 2^-e max|x| lies in [1, 2): every transform (and the spectral
/// peak, the denoiser) first scales its input by 2^-e, exactly, so that nothing
/// overflows or underflows whatever the magnitude; 2^e itself is representable.
inline int PeakExponent(const Eigen::Ref<const Eigen::VectorXd>& x) {
  int exponent = 0;
  std::frexp(x.cwiseAbs().maxCoeff(), &exponent);
  return exponent - 1;
}

/// The message of a step outside kMinStep_s .. kMaxStep_s (or not finite).
inline const char* StepExpectation() { return "a finite value between 1e-15 s and 1e15 s"; }

/// Throws std::invalid_argument for fewer than 4 samples.
inline void CheckSamples(Eigen::Index n) {
  if (n < 4) ThrowInvalid("Cwt: signal", "at least 4 samples", ToText(n) + " samples");
}

/// Throws std::invalid_argument for step_s outside kMinStep_s .. kMaxStep_s,
/// a grid above Nyquist (beyond a rounding of 1e-12) or below
/// kMinFrequencyOverRate of the sampling rate.
inline void CheckStep(double step_s, const FrequencyGrid& grid) {
  if (!IsTransformStep(step_s)) ThrowInvalid("Cwt: step_s", StepExpectation(), ToText(step_s));
  const double nyquist_Hz = 0.5 / step_s;
  if (grid.max_frequency_Hz > nyquist_Hz * (1.0 + 1e-12)) {
    ThrowInvalid("Cwt: frequencies.max_frequency_Hz",
                 "<= the Nyquist frequency 1 / (2 step_s) = " + ToText(nyquist_Hz) + " Hz",
                 ToText(grid.max_frequency_Hz) + " Hz");
  }
  const double lowest_Hz = kMinFrequencyOverRate / step_s;
  if (!(grid.min_frequency_Hz >= lowest_Hz)) {
    ThrowInvalid("Cwt: frequencies.min_frequency_Hz",
                 ">= 1e-20 times the sampling rate 1 / step_s, " + ToText(lowest_Hz) + " Hz",
                 ToText(grid.min_frequency_Hz) + " Hz");
  }
}

/// CheckSamples, then NaN/Inf or a constant signal, then CheckStep.
inline void CheckSignal(const Eigen::Ref<const Eigen::VectorXd>& signal,
                        double step_s,
                        const FrequencyGrid& grid) {
  const Eigen::Index n = signal.size();
  CheckSamples(n);
  if (!signal.allFinite()) ThrowInvalid("Cwt: signal", "finite values", "NaN or Inf");
  if (signal.maxCoeff() == signal.minCoeff()) {
    ThrowInvalid("Cwt: signal", "a non-constant signal",
                 "all " + ToText(n) + " samples equal to " + ToText(signal(0)));
  }
  CheckStep(step_s, grid);
}

}  // namespace podid::wavelet::internal
