#pragma once
// The checks every transform applies to its input, with one set of messages
// (CwtTransform::Compute, WhiteNoiseMagnitude and the streamed ridge).

#include <Eigen/Core>
#include <cmath>

#include "podid/core/error.hpp"
#include "podid/core/time_series.hpp"

namespace podid::wavelet::internal {

/// Every transform scales its input by 2^-e to a peak in [1, 2); the
/// coefficients are returned in signal units when |e| <= this: |W| <= 4
/// sqrt(s) peak|x| then stays far from overflow, and the band's 1e-12 tails
/// far from the subnormal range (CwtTransform, the streamed ridge).
inline constexpr int kMaxUnscaledExponent = 960;
/// The same for single-precision output (float's range is 2^-126 .. 2^128):
/// within 2^+-32 of 1, |W| keeps 2^94 of headroom for the sqrt(s) of the
/// energy normalisation and its 1e-12 tails stay 2^50 above the subnormals;
/// beyond, the float values are in units of coefficient_scale instead of
/// overflowing to inf or flushing to 0 (a tone of amplitude 1e40 or 1e-100).
inline constexpr int kMaxUnscaledFloatExponent = 32;

/// Throws std::invalid_argument for fewer than 4 samples.
inline void CheckSamples(Eigen::Index n) {
  if (n < 4) ThrowInvalid("Cwt: signal", "at least 4 samples", ToText(n) + " samples");
}

/// Throws std::invalid_argument for step_s not a sampling step (finite, > 0,
/// a finite rate: IsSamplingStep), or max_Hz above Nyquist (beyond a
/// rounding of 1e-12).
inline void CheckStep(double step_s, double max_Hz) {
  if (!IsSamplingStep(step_s)) {
    ThrowInvalid("Cwt: step_s", "a finite value > 0 whose rate 1 / step_s is finite",
                 ToText(step_s));
  }
  const double nyquist_Hz = 0.5 / step_s;
  if (max_Hz > nyquist_Hz * (1.0 + 1e-12)) {
    ThrowInvalid("Cwt: frequencies.max_frequency_Hz",
                 "<= the Nyquist frequency 1 / (2 step_s) = " + ToText(nyquist_Hz) + " Hz",
                 ToText(max_Hz) + " Hz");
  }
}

/// CheckSamples, then NaN/Inf or a constant signal, then CheckStep.
inline void CheckSignal(const Eigen::Ref<const Eigen::VectorXd>& signal, double step_s, double max_Hz) {
  const Eigen::Index n = signal.size();
  CheckSamples(n);
  if (!signal.allFinite()) ThrowInvalid("Cwt: signal", "finite values", "NaN or Inf");
  if (signal.maxCoeff() == signal.minCoeff()) {
    ThrowInvalid("Cwt: signal", "a non-constant signal",
                 "all " + ToText(n) + " samples equal to " + ToText(signal(0)));
  }
  CheckStep(step_s, max_Hz);
}

}  // namespace podid::wavelet::internal
