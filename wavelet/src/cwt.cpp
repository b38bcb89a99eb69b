// The Morlet CWT by FFT (podid/wavelet/cwt.hpp): layout, scaling, threads.
#include "podid/wavelet/cwt.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

#include "extent.hpp"
#include "fftw_plans.hpp"
#include "full_rate.hpp"
#include "huge_pages.hpp"
#include "moved_from.hpp"
#include "podid/core/error.hpp"
#include "podid/wavelet/plans.hpp"
#include "pruned_inverse.hpp"
#include "ridge_cost.hpp"
#include "scale_filters.hpp"
#include "signal_check.hpp"

namespace podid::wavelet {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

bool Fail(std::string* why, std::string message) {
  if (why != nullptr) *why = std::move(message);
  return false;
}

// Reflect padding's one jump lies where every coefficient's envelope is
// below this fraction of its peak (5.26 s for Morlet): at the border
// coefficients only (exp(-(5.26 + 1.41)^2 / 2) = 2e-10 inside the cone at
// coi_factor 1). The band tolerance's 7.43 s instead would pad the objective's
// 5001-sample record to 12288 points, not 10240: 5-10 % per evaluation.
constexpr double kReflectJumpWeight = 1e-6;

// The sizes one Compute() allocates for a layout, before allocating them.
struct Sizes {
  Eigen::Index p = 0, m = 0, times = 0, filter_bins = 0;
};

}  // namespace

bool CwtOptions::IsValid(std::string* why) const {
  if (!wavelet.IsValid(why) || !frequencies.IsValid(why)) return false;
  // Above ~6 an edge's influence, exp(-c^2), is below double precision
  // already; 10 leaves room and keeps the cone's frequencies finite.
  if (!(coi_factor >= 0.0 && coi_factor <= kMaxCoiFactor)) {
    return Fail(why, "CwtOptions.coi_factor: expected a value in [0, " + ToText(kMaxCoiFactor) +
                         "], got " + ToText(coi_factor));
  }
  if (!(band_tolerance > 0.0 && band_tolerance <= 1e-3)) {
    return Fail(why, "CwtOptions.band_tolerance: expected a value in (0, 1e-3], got " +
                         ToText(band_tolerance));
  }
  if (threads < 1 || threads > kMaxCwtThreads) {
    return Fail(why, "CwtOptions.threads: expected 1.." + ToText(kMaxCwtThreads) + ", got " +
                         ToText(threads));
  }
  if (!(memory_budget_bytes >= 65536.0 && memory_budget_bytes <= 17592186044416.0)) {
    return Fail(why, "CwtOptions.memory_budget_bytes: expected 2^16..2^44, got " +
                         ToText(memory_budget_bytes));
  }
  // Any other int cast to these left P = 0 (a division by zero) or aborted.
  if (padding != Padding::kReflect && padding != Padding::kZero && padding != Padding::kPeriodic) {
    return Fail(why, "CwtOptions.padding: expected kReflect, kZero or kPeriodic, got " +
                         ToText(static_cast<int>(padding)));
  }
  if (output != CwtOutput::kComplex && output != CwtOutput::kComplexFloat &&
      output != CwtOutput::kMagnitudeFloat) {
    return Fail(why,
                "CwtOptions.output: expected kComplex, kComplexFloat or kMagnitudeFloat, got " +
                    ToText(static_cast<int>(output)));
  }
  if (planning != FftPlanning::kEstimate && planning != FftPlanning::kMeasure) {
    return Fail(why, "CwtOptions.planning: expected kEstimate or kMeasure, got " +
                         ToText(static_cast<int>(planning)));
  }
  return true;
}

// ---------------------------------------------------------------- CwtTransform

struct CwtTransform::Impl {
  CwtOptions options;
  double kappa = 0.0;  // c of the scale convention: f = kappa / (2 pi s)
  double time_spread = 0.0;  // sigma_t of the wavelet
  double band_low = 0.0, band_high = 0.0;  // u where psi^ >= band_tolerance * peak
  Eigen::VectorXd frequencies_Hz;
  Eigen::VectorXd scales_s;

  // Layout for the current (N, step).
  Eigen::Index n = 0;
  double step_s = 0.0;
  Eigen::Index p = 0;  // padded length
  Eigen::Index r = 0;  // reflect padding after the data (the rest wraps before it)
  Eigen::Index m = 0;  // inverse FFT length
  Eigen::Index d = 1;  // decimation
  Eigen::Index times = 0;
  double bin_rad_per_s = 0.0;
  internal::ScaleFilters filters;  // bands and n(s) psi^(s w_b) / P over them
  fftw_plan forward = nullptr;
  fftw_plan backward = nullptr;
  internal::RealBuffer padded;
  internal::ComplexBuffer spectrum;  // P bins of the last signal (bins 0 .. P / 2 used)
  mutable std::vector<internal::ComplexBuffer> work;  // M each, one per thread
  internal::FullRateCwt full_rate;                    // the full-rate path's plans and buffers
  Eigen::VectorXd coi_frequency_Hz;
  double output_scale = 1.0;  // multiplies the scaled transform into Scalogram units
  std::uint64_t computation = 0;  // the last Compute()'s Scalogram::computation, 0: none

  Sizes Plan(Eigen::Index samples, double step) const;
  // Scale k's band at padded length p: bins [*a, *b] (signed; empty if *b < *a).
  void Band(Eigen::Index k, Eigen::Index p, double step, Eigen::Index* a, Eigen::Index* b) const;
  void Layout(Eigen::Index samples, double step);
  // The full-rate path's overlap-save groups at padded length p (blocked_scales.hpp).
  internal::BlockedScales::Grouping BlockGroups(Eigen::Index p,
                                                double step,
                                                Eigen::Index times) const;
  // Every scale's band and gains n(s) psi^(s w_b) / P at padded length p.
  void SetFilters(Eigen::Index p, double step, internal::ScaleFilters* out) const;
  // W (derivative: dW/dt) of scale k at the M decimated times into w.
  void Synthesise(Eigen::Index k, bool derivative, Complex* w) const;
};

void CwtTransform::Impl::Band(Eigen::Index k, Eigen::Index p, double step, Eigen::Index* a,
                              Eigen::Index* b) const {
  const double bin_rad_per_s = 2.0 * kPi / (static_cast<double>(p) * step);
  const double to_bin = 1.0 / (scales_s(k) * bin_rad_per_s);
  *a = std::max(-((p - 1) / 2), static_cast<Eigen::Index>(std::ceil(band_low * to_bin)));
  *b = std::min(p / 2, static_cast<Eigen::Index>(std::floor(band_high * to_bin)));
}

// Every length and count of a layout, from closed forms (nothing allocated).
// Throws std::invalid_argument beyond FFTW plans' 2^27 points, checked on the
// record first so that nothing below overflows (2^63 samples hung).
Sizes CwtTransform::Impl::Plan(Eigen::Index samples, double step) const {
  if (samples > internal::kMaxPlanLength) {
    ThrowInvalid("Cwt: signal", "at most 2^27 = 134217728 samples (FFTs of at most 2^27 points)",
                 ToText(samples) + " samples");
  }
  Sizes z;
  const bool morse = options.wavelet.family == WaveletFamily::kMorse;
  // In samples at the lowest frequency, at a tolerance (of the envelope's peak).
  const auto support_at = [&](double tolerance) {
    return std::ceil(internal::SupportRadius(time_spread, morse, tolerance) * scales_s.maxCoeff() /
                     step);
  };
  const double support = support_at(options.band_tolerance);
  const double nd = static_cast<double>(samples);
  switch (options.padding) {
    case Padding::kReflect: {
      // The padded sequence is the even extension (period 2N - 2) up to one
      // jump, which no envelope may reach above kReflectJumpWeight: N + 2 of
      // these radii, rounded up to a fast length. Where that would cost more
      // than twice one period, P = 2N - 2 itself, which has no jump at all
      // (any factors). A fast length just above 2N - 2 did not suffice: a
      // jump 1.1 s from the data, 2.7e-2 of max |W| inside the cone for 1001
      // samples at 5 kHz down to 10 Hz (docs/wavelet.md, "Algorithm and padding").
      const double period = 2.0 * nd - 2.0;
      const double needed = nd + 2.0 * support_at(kReflectJumpWeight);
      const long long fast =
          needed <= 2.0 * period ? internal::FastFftLength(static_cast<long long>(needed)) : 0;
      z.p = fast != 0 && static_cast<double>(fast) <= 2.0 * period
                ? static_cast<Eigen::Index>(fast)
                : static_cast<Eigen::Index>(period);
      break;
    }
    case Padding::kZero: {
      // As many zeros as the support: W is that of the record followed by
      // zeros for ever (a linear convolution, pywt's fft method). N + min(N,
      // support) let a wavelet longer than the record reach its periodic
      // copy: 8.2e-9 of max |W| inside the cone for Morlet, 8.9e-7 for Morse,
      // at 1001 samples (docs/wavelet.md). Only scales with no sample inside
      // the cone (half-width coi_factor 2 sigma_t s) need more than the
      // largest scale with one: the zeros stop at its support (at least N),
      // so that 1e-17 Hz does not ask 10^20 points.
      double zeros = support;
      if (options.coi_factor > 0) {
        const double edge_s = std::floor((nd - 1.0) / 2.0) * step;
        const double cone_scale_s = edge_s / (options.coi_factor * 2.0 * time_spread);
        const double cone_support =
            std::ceil(internal::SupportRadius(time_spread, morse, options.band_tolerance) *
                      cone_scale_s / step);
        zeros = std::min(support, std::max(nd, cone_support));
      }
      const double needed = nd + zeros;
      if (!(needed <= static_cast<double>(internal::kMaxPlanLength))) {
        ThrowInvalid("Cwt: padded length",
                     "at most 2^27 = 134217728 points (FFTW plans' limit): raise the lowest "
                     "frequency",
                     ToText(needed) + " points for " + ToText(samples) +
                         " samples and the wavelet's support at " +
                         ToText(frequencies_Hz.minCoeff()) + " Hz (zero padding)");
      }
      z.p = internal::FastFftLength(static_cast<long long>(needed));
      break;
    }
    case Padding::kPeriodic:
      z.p = samples;
      break;
  }
  if (z.p > internal::kMaxPlanLength) {
    ThrowInvalid("Cwt: padded length", "at most 2^27 = 134217728 points (FFTW plans' limit)",
                 ToText(z.p) + " points for " + ToText(samples) + " samples (" +
                     ToString(options.padding) + " padding)");
  }
  Eigen::Index widest = 1;
  for (Eigen::Index k = 0; k < scales_s.size(); ++k) {
    Eigen::Index a = 0, b = 0;
    Band(k, z.p, step, &a, &b);
    z.filter_bins += std::max<Eigen::Index>(0, b - a + 1);
    widest = std::max<Eigen::Index>(widest, b - a + 1);
  }
  z.m = z.p;
  if (options.band_limited) {
    for (Eigen::Index candidate = widest; candidate < z.p; ++candidate) {
      if (z.p % candidate == 0) {
        z.m = candidate;
        break;
      }
    }
  }
  z.times = (samples - 1) / (z.p / z.m) + 1;
  return z;
}

void CwtTransform::Impl::Layout(Eigen::Index samples, double step) {
  const Sizes z = Plan(samples, step);
  // Checked before anything is allocated or changed. Memory: coefficients, filters, padded signal,
  // spectrum, work buffers.
  const double per_coefficient = options.output == CwtOutput::kComplex        ? 16.0
                                 : options.output == CwtOutput::kComplexFloat ? 8.0
                                                                              : 4.0;
  // Filters at each overlap-save block length (stored ones only: a band
  // holds at most L + 1 bins of length L).
  const auto BlockFilterBytes = [&](Eigen::Index p) {
    if (p < internal::BlockedScales::kMinPaddedLength) return 0.0;
    Eigen::Index bins = 0;
    for (Eigen::Index length : internal::BlockedScales::kLengths) bins += length + 1;
    return internal::ScaleFilters::Bytes(options.wavelet,
                                         bins * static_cast<Eigen::Index>(scales_s.size()));
  };
  internal::BlockedScales::Grouping blocked;  // the full-rate path's overlap-save groups
  if (!options.band_limited) blocked = BlockGroups(z.p, step, z.times);
  const double bytes =
      per_coefficient * static_cast<double>(z.times) * static_cast<double>(scales_s.size()) +
      internal::ScaleFilters::Bytes(options.wavelet, z.filter_bins) +
      8.0 * static_cast<double>(z.p) + 16.0 * static_cast<double>(z.p) +
      16.0 * static_cast<double>(z.m) * options.threads +
      (options.band_limited ? 0.0 : internal::FullRateCwt::Bytes(z.p, options.threads, blocked)) +
      (options.band_limited ? 0.0 : BlockFilterBytes(z.p));
  if (bytes > options.memory_budget_bytes) {
    ThrowInvalid("Cwt: memory",
                 "at most " + ToText(options.memory_budget_bytes) +
                     " bytes (CwtOptions::memory_budget_bytes)",
                 ToText(bytes) + " bytes for " + ToText(z.times) + " output times x " +
                     ToText(scales_s.size()) + " frequencies x " + ToText(per_coefficient) +
                     " bytes, " + ToText(z.filter_bins) + " filter bins and FFTs of " +
                     ToText(z.p) +
                     " points (fewer frequencies, a higher min_frequency_Hz or band_limited)");
  }
  n = samples;
  step_s = step;
  p = z.p;
  m = z.m;
  d = p / m;
  times = z.times;
  r = (p - n + 1) / 2;
  bin_rad_per_s = 2.0 * kPi / (static_cast<double>(p) * step_s);
  SetFilters(p, step_s, &filters);
  const bool measure = options.planning == FftPlanning::kMeasure;
  forward = internal::ComplexForwardPlan(static_cast<int>(p), measure);
  backward = internal::ComplexBackwardPlan(static_cast<int>(m), measure);
  padded = internal::AllocateReal(static_cast<std::size_t>(p));
  spectrum = internal::AllocateComplex(static_cast<std::size_t>(p));
  work.clear();
  for (int t = 0; t < options.threads; ++t) {
    work.push_back(internal::AllocateComplex(static_cast<std::size_t>(m)));
  }
  if (!options.band_limited) {
    full_rate.Layout(
        p, filters, std::move(blocked),
        [this](Eigen::Index length, internal::ScaleFilters* out) {
          SetFilters(length, step_s, out);
        },
        options.threads, measure);
  }
  coi_frequency_Hz.resize(times);
  for (Eigen::Index j = 0; j < times; ++j) {
    const Eigen::Index sample = j * d;
    const double edge_s = static_cast<double>(std::min(sample, n - 1 - sample)) * step_s;
    coi_frequency_Hz(j) =
        internal::ConeFrequency_Hz(options.coi_factor, kappa, time_spread, edge_s);
  }
}

internal::BlockedScales::Grouping CwtTransform::Impl::BlockGroups(Eigen::Index p,
                                                                  double step,
                                                                  Eigen::Index times) const {
  const bool morse = options.wavelet.family == WaveletFamily::kMorse;
  const double radius = internal::SupportRadius(time_spread, morse, options.band_tolerance);
  const double bin = 2.0 * kPi / (static_cast<double>(p) * step);
  std::vector<internal::BlockedScales::Scale> scales(static_cast<std::size_t>(scales_s.size()));
  for (Eigen::Index k = 0; k < scales_s.size(); ++k) {
    Eigen::Index a = 0, b = 0;
    Band(k, p, step, &a, &b);
    // Band() clips at -(P - 1) / 2 and P / 2: a band that reaches either is
    // cut there, and its kernel is not compact in time.
    const double to_bin = 1.0 / (scales_s(k) * bin);
    auto& scale = scales[static_cast<std::size_t>(k)];
    scale.decimation = internal::PrunedInverse::Decimation(p, std::max<Eigen::Index>(b - a + 1, 1));
    scale.inside = b >= a && band_low * to_bin > static_cast<double>(-((p - 1) / 2)) &&
                   band_high * to_bin < static_cast<double>(p / 2);
    scale.support = radius * scales_s(k) / step;
  }
  internal::BlockedScales::Grouping grouping = internal::BlockedScales::Plan(p, times, scales);
  // Each group keeps the bins its bands reach at its block length.
  for (Eigen::Index k = 0; k < scales_s.size(); ++k) {
    const int g = grouping.group[static_cast<std::size_t>(k)];
    if (g < 0) continue;
    auto& group = grouping.groups[static_cast<std::size_t>(g)];
    Eigen::Index a = 0, b = 0;
    Band(k, group.length, step, &a, &b);
    group.bins = std::max({group.bins, b + 1, 1 - a});
  }
  return grouping;
}

void CwtTransform::Impl::SetFilters(Eigen::Index p, double step, internal::ScaleFilters* out) const {
  const double bin = 2.0 * kPi / (static_cast<double>(p) * step);
  const bool energy = options.wavelet.normalisation == Normalisation::kEnergy;
  const Eigen::Index scales = scales_s.size();
  out->Reset(options.wavelet, scales);
  for (Eigen::Index k = 0; k < scales; ++k) {
    const double s = scales_s(k);
    Eigen::Index a = 0, b = 0;
    Band(k, p, step, &a, &b);
    const double norm = (energy ? std::sqrt(s) : 1.0) / static_cast<double>(p);
    out->Set(k, a, b, s, norm, bin);
  }
}

void CwtTransform::Impl::Synthesise(Eigen::Index k, bool derivative, Complex* w) const {
  std::fill(w, w + m, Complex(0.0, 0.0));
  const internal::ScaleFilter filter = filters.Filter(k);
  double scratch[internal::ScaleFilter::kChunkBins];
  const double* gains = scratch;
  const Eigen::Index a = filters.first(k);
  const Complex* x = spectrum.get();
  const Eigen::Index size = filters.bins(k);
  // Bin b lands at b mod M: at the decimated times t_j = j D step the
  // exponentials exp(i 2 pi b j / M) are M-periodic in b, and the band (<= M
  // bins) never folds onto itself.
  Eigen::Index slot = ((a % m) + m) % m;
  for (Eigen::Index i = 0; i < size; ++i) {
    const Eigen::Index bin = a + i;
    const Complex value = bin >= 0 ? x[bin] : std::conj(x[-bin]);
    const Eigen::Index chunk = i % internal::ScaleFilter::kChunkBins;
    if (chunk == 0) {
      gains = filter.Values(i, std::min(size - i, internal::ScaleFilter::kChunkBins), scratch);
    }
    const double gain = gains[chunk];
    if (derivative) {
      w[slot] = value * Complex(0.0, gain * static_cast<double>(bin) * bin_rad_per_s);
    } else {
      w[slot] = value * gain;
    }
    if (++slot == m) slot = 0;
  }
  fftw_execute_dft(backward, internal::AsFftw(w), internal::AsFftw(w));
}

CwtTransform::CwtTransform(const CwtOptions& options) : impl_(std::make_unique<Impl>()) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument(why);
  impl_->options = options;
  impl_->kappa = options.wavelet.ScaleFrequencyConstant();
  impl_->time_spread = options.wavelet.TimeSpread();
  options.wavelet.Band(options.band_tolerance, &impl_->band_low, &impl_->band_high);
  impl_->frequencies_Hz = options.frequencies.Frequencies_Hz();
  impl_->scales_s = impl_->kappa / (2.0 * kPi) * impl_->frequencies_Hz.cwiseInverse();
}

CwtTransform::~CwtTransform() = default;
CwtTransform::CwtTransform(CwtTransform&&) noexcept = default;
CwtTransform& CwtTransform::operator=(CwtTransform&&) noexcept = default;

namespace {
constexpr const char* kOwner = "CwtTransform";
}  // namespace

const CwtOptions& CwtTransform::options() const {
  return internal::CheckedImpl(impl_, kOwner).options;
}
Eigen::Index CwtTransform::padded_length() const { return internal::CheckedImpl(impl_, kOwner).p; }
Eigen::Index CwtTransform::inverse_length() const { return internal::CheckedImpl(impl_, kOwner).m; }

void CwtTransform::Compute(const Eigen::Ref<const Eigen::VectorXd>& signal,
                           double step_s,
                           Scalogram* out,
                           double start_time_s) {
  Impl& s = internal::CheckedImpl(impl_, kOwner);
  if (out == nullptr) {
    throw std::invalid_argument("CwtTransform::Compute: expected a Scalogram to write, got null");
  }
  const Eigen::Index n = signal.size();
  internal::CheckSignal(signal, step_s, s.options.frequencies);
  if (!std::isfinite(start_time_s)) {
    ThrowInvalid("Cwt: start_time_s", "a finite value", ToText(start_time_s));
  }
  // The spectrum and layout are about to change: an earlier scalogram's
  // TimeDerivative is gone, and if this call throws there is no new one.
  s.computation = 0;
  if (n != s.n || step_s != s.step_s) s.Layout(n, step_s);

  // Scale by 2^-e (exact) to a peak in [1, 2): no overflow in the mean or
  // the FFT, no underflow in |W|^2, whatever the signal's magnitude; 2^e
  // itself is representable (e <= 1023 for the largest double).
  const int exponent = internal::PeakExponent(signal);
  double* x = s.padded.get();
  for (Eigen::Index i = 0; i < n; ++i) x[i] = std::ldexp(signal(i), -exponent);
  if (s.options.remove_mean) {
    const double mean = Eigen::Map<const Eigen::VectorXd>(x, n).mean();
    for (Eigen::Index i = 0; i < n; ++i) x[i] -= mean;
  }
  if (s.options.padding == Padding::kReflect) {
    for (Eigen::Index i = n; i < n + s.r; ++i) x[i] = x[internal::Mirror(i, n)];
    for (Eigen::Index i = n + s.r; i < s.p; ++i) x[i] = x[internal::Mirror(i - s.p, n)];
  } else if (s.options.padding == Padding::kZero) {
    std::fill(x + n, x + s.p, 0.0);
  }
  // A complex FFT of the real sequence (plans far faster than r2c; fftw_plans.hpp).
  Complex* spectrum = s.spectrum.get();
  for (Eigen::Index i = 0; i < s.p; ++i) spectrum[i] = Complex(x[i], 0.0);
  fftw_execute_dft(s.forward, internal::AsFftw(spectrum), internal::AsFftw(spectrum));
  const bool unscaled = std::abs(exponent) <= (s.options.output == CwtOutput::kComplex
                                                   ? internal::kMaxUnscaledExponent
                                                   : internal::kMaxUnscaledFloatExponent);
  s.output_scale = unscaled ? std::ldexp(1.0, exponent) : 1.0;

  // Process-wide: no two Compute() calls, of any transform, share a number.
  static std::atomic<std::uint64_t> computations{0};
  s.computation = ++computations;
  const Eigen::Index scales = s.scales_s.size();
  out->computation = s.computation;
  out->wavelet = s.options.wavelet;
  out->frequencies_Hz = s.frequencies_Hz;
  out->scales_s = s.scales_s;
  out->step_s = step_s * static_cast<double>(s.d);
  out->decimation = static_cast<int>(s.d);
  out->input_samples = n;
  out->coefficient_scale = unscaled ? 1.0 : std::ldexp(1.0, exponent);
  out->time_s =
      Eigen::VectorXd::LinSpaced(s.times, 0.0, static_cast<double>(s.times - 1)) * out->step_s +
      Eigen::VectorXd::Constant(s.times, start_time_s);
  out->coi_frequency_Hz = s.coi_frequency_Hz;
  // Exactly one output matrix is sized; the others are emptied.
  const CwtOutput output = s.options.output;
  out->coefficients.resize(output == CwtOutput::kComplex ? s.times : 0,
                           output == CwtOutput::kComplex ? scales : 0);
  out->coefficients_float.resize(output == CwtOutput::kComplexFloat ? s.times : 0,
                                 output == CwtOutput::kComplexFloat ? scales : 0);
  out->magnitude.resize(output == CwtOutput::kMagnitudeFloat ? s.times : 0,
                        output == CwtOutput::kMagnitudeFloat ? scales : 0);
  internal::AdviseHugePages(out->coefficients.data(),
                            static_cast<std::size_t>(out->coefficients.size()) * sizeof(Complex));
  internal::AdviseHugePages(
      out->coefficients_float.data(),
      static_cast<std::size_t>(out->coefficients_float.size()) * sizeof(std::complex<float>));
  internal::AdviseHugePages(out->magnitude.data(),
                            static_cast<std::size_t>(out->magnitude.size()) * sizeof(float));
  if (!s.options.band_limited) {
    s.full_rate.Compute(s.spectrum.get(), s.padded.get(), s.times, s.output_scale,
                        {.complex = out->coefficients.data(),
                         .complex_float = out->coefficients_float.data(),
                         .magnitude = out->magnitude.data()});
    return;
  }
  // Scales handed out one at a time: a thread that could not be started
  // leaves its share to the others (not a std::terminate from a joinable pool).
  std::atomic<Eigen::Index> next_scale{0};
  const auto run = [&](int thread) {
    Complex* w = s.work[static_cast<std::size_t>(thread)].get();
    for (Eigen::Index k = next_scale++; k < scales; k = next_scale++) {
      s.Synthesise(k, false, w);
      if (output == CwtOutput::kMagnitudeFloat) {
        // |W| of the scaled transform (no overflow), rounded once to float.
        internal::MagnitudesToFloat(w, s.times, s.output_scale, out->magnitude.col(k).data());
      } else if (output == CwtOutput::kComplexFloat) {
        std::complex<float>* column = out->coefficients_float.col(k).data();
        for (Eigen::Index j = 0; j < s.times; ++j) {
          column[j] = std::complex<float>(static_cast<float>(w[j].real() * s.output_scale),
                                          static_cast<float>(w[j].imag() * s.output_scale));
        }
      } else if (s.output_scale == 1.0) {
        std::copy(w, w + s.times, out->coefficients.col(k).data());
      } else {
        Complex* column = out->coefficients.col(k).data();
        for (Eigen::Index j = 0; j < s.times; ++j) column[j] = w[j] * s.output_scale;
      }
    }
  };
  const int workers = static_cast<int>(std::min<Eigen::Index>(s.options.threads, scales));
  std::vector<std::thread> pool;
  for (int t = 1; t < workers; ++t) {
    try {
      pool.emplace_back(run, t);
    } catch (const std::system_error&) {
      break;  // no more threads: the running ones take the remaining scales
    }
  }
  run(0);
  for (auto& thread : pool) thread.join();
}

void CwtTransform::TimeDerivative(Eigen::Index frequency_index, Eigen::VectorXcd* out) const {
  const Impl& s = internal::CheckedImpl(impl_, kOwner);
  if (out == nullptr) {
    throw std::invalid_argument("TimeDerivative: expected a vector to write, got null");
  }
  if (s.computation == 0) {
    ThrowInvalid("TimeDerivative: transform", "a Compute() that succeeded first", "none");
  }
  if (frequency_index < 0 || frequency_index >= s.scales_s.size()) {
    ThrowInvalid("TimeDerivative: frequency_index", "0.." + ToText(s.scales_s.size() - 1),
                 ToText(frequency_index));
  }
  Complex* w = s.work.front().get();
  s.Synthesise(frequency_index, true, w);
  out->resize(s.times);
  for (Eigen::Index j = 0; j < s.times; ++j) (*out)(j) = w[j] * s.output_scale;
}

bool CwtTransform::Produced(const Scalogram& scalogram) const {
  const Impl& s = internal::CheckedImpl(impl_, kOwner);
  return s.computation != 0 && scalogram.computation == s.computation &&
         scalogram.times() == s.times && scalogram.frequencies() == s.scales_s.size();
}

Scalogram Cwt(const Eigen::Ref<const Eigen::VectorXd>& signal,
              double step_s,
              const CwtOptions& options) {
  CwtTransform transform(options);
  Scalogram out;
  transform.Compute(signal, step_s, &out);
  return out;
}

FftLengths CwtTransform::Lengths(Eigen::Index samples, double step_s) const {
  if (samples < 4) ThrowInvalid("FFT lengths: samples", "at least 4", ToText(samples));
  if (!IsTransformStep(step_s)) {
    ThrowInvalid("FFT lengths: step_s", internal::StepExpectation(), ToText(step_s));
  }
  const Impl& s = internal::CheckedImpl(impl_, kOwner);
  const Sizes z = s.Plan(samples, step_s);
  FftLengths lengths{{static_cast<int>(z.p)}, {static_cast<int>(z.m)}, {}, {static_cast<int>(z.p)}};
  if (!s.options.band_limited) {
    // The full-rate path's pruned inverses, one plan per distinct D: batches
    // of G inverses of length M = P / D.
    const internal::BlockedScales::Grouping grouping = s.BlockGroups(z.p, step_s, z.times);
    for (Eigen::Index k = 0; k < s.scales_s.size(); ++k) {
      if (grouping.group[static_cast<std::size_t>(k)] >= 0) continue;  // blocked: below
      Eigen::Index a = 0, b = 0;
      s.Band(k, z.p, step_s, &a, &b);
      const Eigen::Index d =
          internal::PrunedInverse::Decimation(z.p, std::max<Eigen::Index>(b - a + 1, 1));
      // A D = 1 scale that may split takes the one inverse of P / 8 (with
      // Debian's FFTW only once measured: measuring it is what `podid plan`
      // is for); in place, one runs on complex_backward's plan of P.
      std::pair<int, int> pair(static_cast<int>(z.p / d),
                               static_cast<int>(internal::PrunedInverse::Batch(z.p, d)));
      if (d == 1 && internal::FullRateCwt::MaySplit(z.p)) {
        pair = {static_cast<int>(z.p / internal::PrunedInverse::kSplitBlocks), 1};
      } else if (d == 1 && z.p >= internal::FullRateCwt::kInPlaceLength) {
        continue;
      }
      auto& list = lengths.interleaved_backward;
      if (std::find(list.begin(), list.end(), pair) == list.end()) list.push_back(pair);
    }
    // The overlap-save blocks: a forward FFT per block length, and each
    // scale's inverse, of L or D' inverses of L / D'.
    for (const auto& group : grouping.groups) {
      auto& forward = lengths.complex_forward;
      const auto length = static_cast<int>(group.length);
      if (std::find(forward.begin(), forward.end(), length) == forward.end()) {
        forward.push_back(length);
      }
    }
    for (Eigen::Index k = 0; k < s.scales_s.size(); ++k) {
      const int g = grouping.group[static_cast<std::size_t>(k)];
      if (g < 0) continue;
      const auto& group = grouping.groups[static_cast<std::size_t>(g)];
      Eigen::Index a = 0, b = 0;
      s.Band(k, group.length, step_s, &a, &b);
      const Eigen::Index inner = internal::BlockedScales::InnerDecimation(group, a, b - a + 1);
      const std::pair<int, int> pair(
          static_cast<int>(group.length / inner),
          static_cast<int>(internal::PrunedInverse::Batch(group.length, inner)));
      auto& list = lengths.interleaved_backward;
      if (std::find(list.begin(), list.end(), pair) == list.end()) list.push_back(pair);
    }
  }
  return lengths;
}

Eigen::VectorXd CwtTransform::WhiteNoiseMagnitude(Eigen::Index samples, double step_s) const {
  const Impl& s = internal::CheckedImpl(impl_, kOwner);
  // Compute()'s checks on the record's size and step (the same messages).
  internal::CheckSamples(samples);
  internal::CheckStep(step_s, s.options.frequencies);
  const Sizes z = s.Plan(samples, step_s);
  // The filters as Layout sets them; a unit impulse has |X_b| = 1 at every
  // bin, so its transform's energy over the P output times is P sum_b g_b^2
  // (the inverse FFT is unnormalised; g carries the 1/P).
  internal::ScaleFilters filters;
  s.SetFilters(z.p, step_s, &filters);
  Eigen::VectorXd out(s.scales_s.size());
  double scratch[internal::ScaleFilter::kChunkBins];
  for (Eigen::Index k = 0; k < out.size(); ++k) {
    const internal::ScaleFilter filter = filters.Filter(k);
    const Eigen::Index bins = filters.bins(k);
    double sum = 0.0;
    for (Eigen::Index i = 0; i < bins; i += internal::ScaleFilter::kChunkBins) {
      const Eigen::Index count = std::min(bins - i, internal::ScaleFilter::kChunkBins);
      const double* g = filter.Values(i, count, scratch);
      for (Eigen::Index j = 0; j < count; ++j) sum += g[j] * g[j];
    }
    out(k) = std::sqrt(static_cast<double>(z.p) * sum);
  }
  return out;
}

FftLengths CwtFftLengths(const CwtOptions& options, Eigen::Index samples, double step_s) {
  return CwtTransform(options).Lengths(samples, step_s);
}

}  // namespace podid::wavelet
