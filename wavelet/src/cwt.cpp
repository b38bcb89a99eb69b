#include "podid/wavelet/cwt.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "fftw_plans.hpp"
#include "podid/core/error.hpp"

namespace podid::wavelet {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

bool Fail(std::string* why, std::string message) {
  if (why != nullptr) *why = std::move(message);
  return false;
}

// Smallest n' >= n whose prime factors are all in {2, 3, 5, 7} (fast for FFTW).
Eigen::Index NextSmoothSize(Eigen::Index n) {
  for (Eigen::Index m = std::max<Eigen::Index>(n, 1);; ++m) {
    Eigen::Index r = m;
    for (Eigen::Index p : {2, 3, 5, 7}) {
      while (r % p == 0) r /= p;
    }
    if (r == 1) return m;
  }
}

}  // namespace

const char* ToString(Normalisation normalisation) {
  return normalisation == Normalisation::kAmplitude ? "amplitude" : "energy";
}
const char* ToString(Padding padding) {
  switch (padding) {
    case Padding::kReflect:
      return "reflect";
    case Padding::kZero:
      return "zero";
    case Padding::kPeriodic:
      return "periodic";
  }
  return "?";
}
const char* ToString(FrequencySpacing spacing) {
  return spacing == FrequencySpacing::kLog ? "log" : "linear";
}

Normalisation ParseNormalisation(std::string_view name) {
  if (name == "amplitude") return Normalisation::kAmplitude;
  if (name == "energy") return Normalisation::kEnergy;
  ThrowInvalid("normalisation", "one of amplitude, energy", "\"" + std::string(name) + "\"");
}

Padding ParsePadding(std::string_view name) {
  if (name == "reflect") return Padding::kReflect;
  if (name == "zero") return Padding::kZero;
  if (name == "periodic") return Padding::kPeriodic;
  ThrowInvalid("padding", "one of reflect, zero, periodic", "\"" + std::string(name) + "\"");
}

// ---------------------------------------------------------------- MorletWavelet

bool MorletWavelet::IsValid(std::string* why) const {
  if (!std::isfinite(omega0) || omega0 <= 0.0) {
    return Fail(why, "MorletWavelet.omega0: expected a finite value > 0, got " + ToText(omega0));
  }
  if (omega0 < 5.0 && !admissibility_correction) {
    return Fail(why,
                "MorletWavelet.omega0: expected >= 5 (or admissibility_correction = true), got " +
                    ToText(omega0));
  }
  if (omega0 > 100.0) {
    return Fail(why, "MorletWavelet.omega0: expected <= 100, got " + ToText(omega0));
  }
  return true;
}

double MorletWavelet::FourierTransform(double u) const {
  const double k = normalisation == Normalisation::kAmplitude
                       ? 2.0                                          // sqrt(2/pi) sqrt(2 pi)
                       : std::sqrt(2.0 * kPi) / std::pow(kPi, 0.25);  // pi^-1/4 sqrt(2 pi)
  const double d = u - omega0;
  double value = std::exp(-0.5 * d * d);
  if (admissibility_correction) value -= std::exp(-0.5 * (u * u + omega0 * omega0));
  return k * value;
}

double MorletWavelet::RidgeAngularFrequency() const {
  const bool energy = normalisation == Normalisation::kEnergy;
  if (!admissibility_correction) {
    return energy ? 0.5 * (omega0 + std::sqrt(omega0 * omega0 + 2.0)) : omega0;
  }
  // d/du log(n(u) psi^(u)) = 0, n(u) = 1 or sqrt(u); the root is bracketed
  // near omega0 and the derivative decreases through it: bisect to rounding.
  const auto slope = [&](double u) {
    const double g = std::exp(-0.5 * (u - omega0) * (u - omega0));
    const double c = std::exp(-0.5 * (u * u + omega0 * omega0));
    const double psi = g - c;
    const double dpsi = -(u - omega0) * g + u * c;
    return dpsi / psi + (energy ? 0.5 / u : 0.0);
  };
  double lo = std::max(1e-3, 0.5 * omega0), hi = omega0 + 2.0;
  PODID_CHECK(slope(lo) > 0.0 && slope(hi) < 0.0);
  for (int i = 0; i < 200 && hi - lo > 4e-16 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (slope(mid) > 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double MorletWavelet::ScaleToFrequency_Hz(double scale_s) const {
  return RidgeAngularFrequency() / (2.0 * kPi * scale_s);
}

double MorletWavelet::FrequencyToScale_s(double frequency_Hz) const {
  return RidgeAngularFrequency() / (2.0 * kPi * frequency_Hz);
}

double MorletWavelet::UnitCosineMagnitude(double scale_s) const {
  const double n = normalisation == Normalisation::kAmplitude ? 1.0 : std::sqrt(scale_s);
  return 0.5 * n * FourierTransform(RidgeAngularFrequency());
}

double MorletWavelet::ConeOfInfluence_s(double scale_s) { return std::sqrt(2.0) * scale_s; }

// ---------------------------------------------------------------- FrequencyGrid

bool FrequencyGrid::IsValid(std::string* why) const {
  if (!std::isfinite(min_frequency_Hz) || min_frequency_Hz <= 0.0) {
    return Fail(why, "FrequencyGrid.min_frequency_Hz: expected a finite value > 0, got " +
                         ToText(min_frequency_Hz));
  }
  if (!std::isfinite(max_frequency_Hz) || max_frequency_Hz <= min_frequency_Hz) {
    return Fail(why,
                "FrequencyGrid.max_frequency_Hz: expected a finite value > min_frequency_Hz (" +
                    ToText(min_frequency_Hz) + "), got " + ToText(max_frequency_Hz));
  }
  if (spacing == FrequencySpacing::kLog && (voices_per_octave < 1 || voices_per_octave > 1024)) {
    return Fail(
        why, "FrequencyGrid.voices_per_octave: expected 1..1024, got " + ToText(voices_per_octave));
  }
  if (spacing == FrequencySpacing::kLinear && (bins < 2 || bins > 100000)) {
    return Fail(why, "FrequencyGrid.bins: expected 2..100000, got " + ToText(bins));
  }
  if (spacing == FrequencySpacing::kLog &&
      voices_per_octave * std::log2(max_frequency_Hz / min_frequency_Hz) > 100000) {
    return Fail(why,
                "FrequencyGrid: expected at most 100000 frequencies, got " +
                    ToText(voices_per_octave * std::log2(max_frequency_Hz / min_frequency_Hz)));
  }
  return true;
}

Eigen::VectorXd FrequencyGrid::Frequencies_Hz() const {
  std::string why;
  if (!IsValid(&why)) throw std::invalid_argument(why);
  if (spacing == FrequencySpacing::kLinear) {
    return Eigen::VectorXd::LinSpaced(bins, min_frequency_Hz, max_frequency_Hz);
  }
  const double octaves = std::log2(max_frequency_Hz / min_frequency_Hz);
  const int count = static_cast<int>(std::floor(voices_per_octave * octaves + 1e-9)) + 1;
  Eigen::VectorXd f(count);
  for (int j = 0; j < count; ++j) {
    f(j) = min_frequency_Hz * std::exp2(static_cast<double>(j) / voices_per_octave);
  }
  return f;
}

// ---------------------------------------------------------------- CwtOptions

bool CwtOptions::IsValid(std::string* why) const {
  if (!wavelet.IsValid(why) || !frequencies.IsValid(why)) return false;
  if (!std::isfinite(coi_factor) || coi_factor < 0.0) {
    return Fail(why,
                "CwtOptions.coi_factor: expected a finite value >= 0, got " + ToText(coi_factor));
  }
  if (!(band_tolerance > 0.0 && band_tolerance <= 1e-3)) {
    return Fail(why, "CwtOptions.band_tolerance: expected a value in (0, 1e-3], got " +
                         ToText(band_tolerance));
  }
  return true;
}

// ---------------------------------------------------------------- CwtTransform

struct CwtTransform::Impl {
  CwtOptions options;
  double kappa = 0.0;
  Eigen::VectorXd frequencies_Hz;
  Eigen::VectorXd scales_s;

  // Layout for the current (N, step).
  Eigen::Index n = 0;
  double step_s = 0.0;
  Eigen::Index p = 0;  // padded length
  Eigen::Index m = 0;  // inverse FFT length
  Eigen::Index d = 1;  // decimation
  Eigen::Index times = 0;
  double bin_rad_per_s = 0.0;
  std::vector<Eigen::Index> band_first;      // signed first bin of each scale's band
  std::vector<std::vector<double>> filters;  // n(s) psi^(s w_b) / P over the band
  fftw_plan forward = nullptr;
  fftw_plan backward = nullptr;
  internal::RealBuffer padded;
  internal::ComplexBuffer spectrum;      // P / 2 + 1 bins of the last signal
  mutable internal::ComplexBuffer work;  // M
  Eigen::VectorXd coi_frequency_Hz;

  void Layout(Eigen::Index samples, double step);
  void Synthesise(Eigen::Index k, bool derivative) const;
};

void CwtTransform::Impl::Layout(Eigen::Index samples, double step) {
  n = samples;
  step_s = step;
  switch (options.padding) {
    case Padding::kReflect:
      p = 2 * n - 2;
      break;
    case Padding::kZero:
      p = NextSmoothSize(2 * n);
      break;
    case Padding::kPeriodic:
      p = n;
      break;
  }
  bin_rad_per_s = 2.0 * kPi / (static_cast<double>(p) * step_s);
  const double omega0 = options.wavelet.omega0;
  const double radius = std::sqrt(2.0 * std::log(1.0 / options.band_tolerance));
  // The correction term exp(-(u^2 + omega0^2) / 2) exceeds the tolerance for
  // |u| < sqrt(radius^2 - omega0^2): keep those bins too.
  const double band_low =
      std::min(omega0 - radius, options.wavelet.admissibility_correction
                                    ? -std::sqrt(std::max(0.0, radius * radius - omega0 * omega0))
                                    : 0.0);
  const Eigen::Index lowest = -((p - 1) / 2), highest = p / 2;
  const bool energy = options.wavelet.normalisation == Normalisation::kEnergy;
  const Eigen::Index scales = scales_s.size();
  band_first.assign(static_cast<std::size_t>(scales), 0);
  filters.assign(static_cast<std::size_t>(scales), {});
  Eigen::Index widest = 1;
  for (Eigen::Index k = 0; k < scales; ++k) {
    const double s = scales_s(k);
    const double to_bin = 1.0 / (s * bin_rad_per_s);
    const Eigen::Index a =
        std::max(lowest, static_cast<Eigen::Index>(std::ceil(band_low * to_bin)));
    const Eigen::Index b =
        std::min(highest, static_cast<Eigen::Index>(std::floor((omega0 + radius) * to_bin)));
    const double norm = (energy ? std::sqrt(s) : 1.0) / static_cast<double>(p);
    auto& filter = filters[static_cast<std::size_t>(k)];
    filter.clear();
    for (Eigen::Index bin = a; bin <= b; ++bin) {
      filter.push_back(norm * options.wavelet.FourierTransform(s * bin * bin_rad_per_s));
    }
    band_first[static_cast<std::size_t>(k)] = a;
    widest = std::max<Eigen::Index>(widest, b - a + 1);
  }
  m = p;
  if (options.band_limited) {
    for (Eigen::Index candidate = widest; candidate < p; ++candidate) {
      if (p % candidate == 0) {
        m = candidate;
        break;
      }
    }
  }
  d = p / m;
  times = (n - 1) / d + 1;
  forward = internal::RealForwardPlan(static_cast<int>(p));
  backward = internal::ComplexBackwardPlan(static_cast<int>(m));
  padded = internal::AllocateReal(static_cast<std::size_t>(p));
  spectrum = internal::AllocateComplex(static_cast<std::size_t>(p / 2 + 1));
  work = internal::AllocateComplex(static_cast<std::size_t>(m));
  coi_frequency_Hz.resize(times);
  for (Eigen::Index j = 0; j < times; ++j) {
    const Eigen::Index sample = j * d;
    const double edge_s = static_cast<double>(std::min(sample, n - 1 - sample)) * step_s;
    coi_frequency_Hz(j) = edge_s > 0.0
                              ? options.coi_factor * kappa * std::sqrt(2.0) / (2.0 * kPi * edge_s)
                              : std::numeric_limits<double>::infinity();
  }
}

void CwtTransform::Impl::Synthesise(Eigen::Index k, bool derivative) const {
  Complex* w = work.get();
  std::fill(w, w + m, Complex(0.0, 0.0));
  const auto& filter = filters[static_cast<std::size_t>(k)];
  const Eigen::Index a = band_first[static_cast<std::size_t>(k)];
  const Complex* x = spectrum.get();
  const Eigen::Index size = static_cast<Eigen::Index>(filter.size());
  // Bin b lands at b mod M: at the decimated times t_j = j D step the
  // exponentials exp(i 2 pi b j / M) are M-periodic in b, and the band (<= M
  // bins) never folds onto itself.
  Eigen::Index slot = ((a % m) + m) % m;
  for (Eigen::Index i = 0; i < size; ++i) {
    const Eigen::Index bin = a + i;
    const Complex value = bin >= 0 ? x[bin] : std::conj(x[-bin]);
    double gain = filter[static_cast<std::size_t>(i)];
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
  impl_->kappa = options.wavelet.RidgeAngularFrequency();
  impl_->frequencies_Hz = options.frequencies.Frequencies_Hz();
  impl_->scales_s = impl_->kappa / (2.0 * kPi) * impl_->frequencies_Hz.cwiseInverse();
}

CwtTransform::~CwtTransform() = default;
CwtTransform::CwtTransform(CwtTransform&&) noexcept = default;
CwtTransform& CwtTransform::operator=(CwtTransform&&) noexcept = default;

const CwtOptions& CwtTransform::options() const { return impl_->options; }
Eigen::Index CwtTransform::padded_length() const { return impl_->p; }
Eigen::Index CwtTransform::inverse_length() const { return impl_->m; }

void CwtTransform::Compute(const Eigen::Ref<const Eigen::VectorXd>& signal,
                           double step_s,
                           Scalogram* out,
                           double start_time_s) {
  PODID_CHECK(out != nullptr);
  Impl& s = *impl_;
  const Eigen::Index n = signal.size();
  if (n < 4) ThrowInvalid("Cwt: signal", "at least 4 samples", ToText(n) + " samples");
  if (!signal.allFinite()) ThrowInvalid("Cwt: signal", "finite values", "NaN or Inf");
  if (signal.maxCoeff() == signal.minCoeff()) {
    ThrowInvalid("Cwt: signal", "a non-constant signal",
                 "all " + ToText(n) + " samples equal to " + ToText(signal(0)));
  }
  if (!std::isfinite(step_s) || step_s <= 0.0) {
    ThrowInvalid("Cwt: step_s", "a finite value > 0", ToText(step_s));
  }
  if (!std::isfinite(start_time_s)) {
    ThrowInvalid("Cwt: start_time_s", "a finite value", ToText(start_time_s));
  }
  const double nyquist_Hz = 0.5 / step_s;
  const double max_Hz = s.options.frequencies.max_frequency_Hz;
  if (max_Hz > nyquist_Hz * (1.0 + 1e-12)) {
    ThrowInvalid("Cwt: frequencies.max_frequency_Hz",
                 "<= the Nyquist frequency 1 / (2 step_s) = " + ToText(nyquist_Hz) + " Hz",
                 ToText(max_Hz) + " Hz");
  }
  if (n != s.n || step_s != s.step_s) s.Layout(n, step_s);

  const double mean = s.options.remove_mean ? signal.mean() : 0.0;
  double* x = s.padded.get();
  for (Eigen::Index i = 0; i < n; ++i) x[i] = signal(i) - mean;
  if (s.options.padding == Padding::kReflect) {
    for (Eigen::Index j = 0; j < n - 2; ++j) x[n + j] = x[n - 2 - j];
  } else if (s.options.padding == Padding::kZero) {
    std::fill(x + n, x + s.p, 0.0);
  }
  fftw_execute_dft_r2c(s.forward, x, internal::AsFftw(s.spectrum.get()));

  const Eigen::Index scales = s.scales_s.size();
  out->wavelet = s.options.wavelet;
  out->frequencies_Hz = s.frequencies_Hz;
  out->scales_s = s.scales_s;
  out->step_s = step_s * static_cast<double>(s.d);
  out->decimation = static_cast<int>(s.d);
  out->input_samples = n;
  out->time_s =
      Eigen::VectorXd::LinSpaced(s.times, 0.0, static_cast<double>(s.times - 1)) * out->step_s +
      Eigen::VectorXd::Constant(s.times, start_time_s);
  out->coi_frequency_Hz = s.coi_frequency_Hz;
  out->coefficients.resize(s.times, scales);
  for (Eigen::Index k = 0; k < scales; ++k) {
    s.Synthesise(k, false);
    std::copy(s.work.get(), s.work.get() + s.times, out->coefficients.col(k).data());
  }
}

void CwtTransform::TimeDerivative(Eigen::Index frequency_index, Eigen::VectorXcd* out) const {
  PODID_CHECK(out != nullptr);
  const Impl& s = *impl_;
  PODID_CHECK_MSG(s.n > 0, "TimeDerivative before Compute");
  PODID_CHECK(frequency_index >= 0 && frequency_index < s.scales_s.size());
  s.Synthesise(frequency_index, true);
  out->resize(s.times);
  std::copy(s.work.get(), s.work.get() + s.times, out->data());
}

Scalogram Cwt(const Eigen::Ref<const Eigen::VectorXd>& signal,
              double step_s,
              const CwtOptions& options) {
  CwtTransform transform(options);
  Scalogram out;
  transform.Compute(signal, step_s, &out);
  return out;
}

}  // namespace podid::wavelet
