#include "podid/wavelet/spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "fftw_plans.hpp"
#include "podid/core/error.hpp"
#include "podid/core/time_series.hpp"
#include "signal_check.hpp"

namespace podid::wavelet {

double SpectralPeak_Hz(const Eigen::Ref<const Eigen::VectorXd>& signal, double step_s,
                       double min_Hz, double max_Hz, const std::vector<double>& exclude_Hz,
                       double exclude_octaves) {
  const Eigen::Index n = signal.size();
  if (n < 8) ThrowInvalid("SpectralPeak_Hz: signal", "at least 8 samples", ToText(n));
  if (!IsSamplingStep(step_s)) {
    ThrowInvalid("SpectralPeak_Hz: step_s", "> 0 with a finite rate 1 / step_s", ToText(step_s));
  }
  if (!(min_Hz >= 0 && min_Hz < max_Hz && std::isfinite(max_Hz))) {
    ThrowInvalid("SpectralPeak_Hz: band", "0 <= min < max", ToText(min_Hz) + ".." + ToText(max_Hz));
  }
  if (!(exclude_octaves >= 0 && exclude_octaves <= 10)) {
    ThrowInvalid("SpectralPeak_Hz: exclude_octaves", "0..10", ToText(exclude_octaves));
  }
  if (!signal.allFinite()) ThrowInvalid("SpectralPeak_Hz: signal", "finite values", "NaN or Inf");
  if (n > (1 << 27)) ThrowInvalid("SpectralPeak_Hz: signal", "at most 2^27 samples", ToText(n));

  const int length = static_cast<int>(n);
  internal::RealBuffer x = internal::AllocateReal(static_cast<std::size_t>(length));
  internal::ComplexBuffer spectrum = internal::AllocateComplex(static_cast<std::size_t>(length / 2 + 1));
  // Scale by 2^-e (exact, as Cwt does) to a peak in [1, 2): the mean and
  // |X|^2 overflowed to NaN at amplitude 1e160 and flushed to 0 at 1e-170.
  // The peak's bin and refinement are the same for any power of two.
  const int exponent = internal::PeakExponent(signal);
  for (int i = 0; i < length; ++i) x[i] = std::ldexp(signal[i], -exponent);
  const double mean = Eigen::Map<const Eigen::VectorXd>(x.get(), n).mean();
  for (int i = 0; i < length; ++i) {
    const double hann = 0.5 - 0.5 * std::cos(2.0 * M_PI * i / (length - 1));
    x[i] = hann * (x[i] - mean);
  }
  fftw_execute_dft_r2c(internal::RealForwardPlan(length, false), x.get(), internal::AsFftw(spectrum.get()));

  // length * step_s overflows for steps near the largest double; 1 / step_s
  // is finite (IsSamplingStep), so the bin is then > 0 all the same.
  const double record_s = length * step_s;
  const double bin_Hz = std::isfinite(record_s) ? 1.0 / record_s : 1.0 / step_s / length;
  // Clamped in double before the cast: a band of 3e9 Hz over 1 Hz bins was
  // out of int's range (UB). f / bin_Hz is >= 0 and never NaN (bin_Hz > 0).
  const double top = length / 2;
  const int first = static_cast<int>(std::clamp(std::ceil(min_Hz / bin_Hz), 1.0, top + 1.0));
  const int last = static_cast<int>(std::clamp(std::floor(max_Hz / bin_Hz), 0.0, top));
  if (first > last) {
    ThrowInvalid("SpectralPeak_Hz: band", "a range holding a periodogram bin (resolution " +
                                              ToText(bin_Hz) + " Hz)",
                 ToText(min_Hz) + ".." + ToText(max_Hz) + " Hz");
  }
  // Power, its prefix sums for the +-1 % average, and the excluded bins.
  const int bins = length / 2 + 1;
  std::vector<double> prefix(bins + 1, 0.0);
  for (int k = 0; k < bins; ++k) prefix[k + 1] = prefix[k] + std::norm(spectrum[k]);
  auto smoothed = [&](int k) {
    const int half = std::max(1, k / 100);
    const int lo = std::max(1, k - half), hi = std::min(bins - 1, k + half);
    return (prefix[hi + 1] - prefix[lo]) / (hi - lo + 1);
  };
  auto excluded = [&](int k) {
    const double f = k * bin_Hz;
    for (double x : exclude_Hz) {
      if (x > 0 && std::abs(std::log2(f / x)) < exclude_octaves) return true;
    }
    return false;
  };
  int best = -1;
  double best_power = 0.0;
  for (int k = first; k <= last; ++k) {
    if (excluded(k)) continue;
    const double power = smoothed(k);
    if (best < 0 || power > best_power) {
      best = k;
      best_power = power;
    }
  }
  if (best < 0 || !(best_power > 0)) return std::numeric_limits<double>::quiet_NaN();
  const double peak = smoothed(best);
  double offset = 0.0;
  if (best > 1 && best < length / 2) {
    const double a = std::log(smoothed(best - 1) + peak * 1e-300);
    const double b = std::log(peak);
    const double c = std::log(smoothed(best + 1) + peak * 1e-300);
    const double curvature = a - 2.0 * b + c;
    if (curvature < 0) offset = std::clamp(0.5 * (a - c) / curvature, -0.5, 0.5);
  }
  return (best + offset) * bin_Hz;
}

Eigen::VectorXd WhiteNoiseMagnitude(const CwtOptions& options, Eigen::Index samples, double step_s) {
  // The filters' energies (Parseval) of the full-rate, zero-padded transform
  // (the padding sets P and so the bins), not the transform of a unit
  // impulse: that kept samples x frequencies complex coefficients (241 MB
  // for the Silverbox's 131,072 x 115, 1.8 GB at 10^6 samples) for one
  // number a frequency.
  CwtOptions zero_padded = options;
  zero_padded.padding = Padding::kZero;
  return CwtTransform(zero_padded).WhiteNoiseMagnitude(samples, step_s);
}

}  // namespace podid::wavelet
