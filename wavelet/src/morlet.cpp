// The Morlet wavelet, the frequency grid and the names of the options
// (podid/wavelet/cwt.hpp).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "podid/core/error.hpp"
#include "podid/wavelet/cwt.hpp"

namespace podid::wavelet {
namespace {

using Complex = std::complex<double>;
constexpr double kPi = std::numbers::pi;

bool Fail(std::string* why, std::string message) {
  if (why != nullptr) *why = std::move(message);
  return false;
}

// The wavelet's own computations (band, time spread, ridge) on invalid
// parameters: a NaN gamma bisected forever, a NaN omega0 returned NaN.
void ThrowIfInvalid(const MorletWavelet& wavelet) {
  std::string why;
  if (!wavelet.IsValid(&why)) throw std::invalid_argument(why);
}

}  // namespace

const char* ToString(Normalisation normalisation) {
  return normalisation == Normalisation::kAmplitude ? "amplitude" : "energy";
}
const char* ToString(WaveletFamily family) {
  return family == WaveletFamily::kMorlet ? "morlet" : "morse";
}

WaveletFamily ParseWaveletFamily(std::string_view name) {
  if (name == "morlet") return WaveletFamily::kMorlet;
  if (name == "morse") return WaveletFamily::kMorse;
  ThrowInvalid("wavelet", "one of morlet, morse", Excerpt(name));
}

const char* ToString(ScaleConvention convention) {
  return convention == ScaleConvention::kRidge ? "ridge" : "peak";
}

ScaleConvention ParseScaleConvention(std::string_view name) {
  if (name == "ridge") return ScaleConvention::kRidge;
  if (name == "peak") return ScaleConvention::kPeak;
  ThrowInvalid("scale convention", "one of ridge, peak", Excerpt(name));
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
  ThrowInvalid("normalisation", "one of amplitude, energy", Excerpt(name));
}

const char* ToString(CwtOutput output) {
  switch (output) {
    case CwtOutput::kComplex:
      return "complex";
    case CwtOutput::kMagnitudeFloat:
      return "magnitude";
    case CwtOutput::kComplexFloat:
      return "complex-float";
  }
  return "?";
}

CwtOutput ParseCwtOutput(std::string_view name) {
  if (name == "complex") return CwtOutput::kComplex;
  if (name == "magnitude") return CwtOutput::kMagnitudeFloat;
  if (name == "complex-float") return CwtOutput::kComplexFloat;
  ThrowInvalid("output", "one of complex, magnitude, complex-float", Excerpt(name));
}

Padding ParsePadding(std::string_view name) {
  if (name == "reflect") return Padding::kReflect;
  if (name == "zero") return Padding::kZero;
  if (name == "periodic") return Padding::kPeriodic;
  ThrowInvalid("padding", "one of reflect, zero, periodic", Excerpt(name));
}

// ---------------------------------------------------------------- MorletWavelet

bool MorletWavelet::IsValid(std::string* why) const {
  // The enums are ints underneath: a cast of any other value reached the
  // transforms and was read differently by each (max |W| 0.054 for 1).
  if (family != WaveletFamily::kMorlet && family != WaveletFamily::kMorse) {
    return Fail(why, "MorletWavelet.family: expected kMorlet or kMorse, got " +
                         ToText(static_cast<int>(family)));
  }
  if (normalisation != Normalisation::kAmplitude && normalisation != Normalisation::kEnergy) {
    return Fail(why, "MorletWavelet.normalisation: expected kAmplitude or kEnergy, got " +
                         ToText(static_cast<int>(normalisation)));
  }
  if (convention != ScaleConvention::kRidge && convention != ScaleConvention::kPeak) {
    return Fail(why, "MorletWavelet.convention: expected kRidge or kPeak, got " +
                         ToText(static_cast<int>(convention)));
  }
  // Both families' parameters, whichever is used: a NaN or negative one is a
  // mistake wherever it was set (the bindings passed gamma = NaN to Morlet).
  if (!std::isfinite(gamma) || gamma < kMinMorseGamma || gamma > kMaxMorseGamma) {
    return Fail(why, "MorletWavelet.gamma: expected a value in [" + ToText(kMinMorseGamma) + ", " +
                         ToText(kMaxMorseGamma) + "], got " + ToText(gamma));
  }
  if (!std::isfinite(beta) || beta < kMinMorseBeta || beta > kMaxMorseBeta) {
    return Fail(why, "MorletWavelet.beta: expected a value in [" + ToText(kMinMorseBeta) + ", " +
                         ToText(kMaxMorseBeta) + "], got " + ToText(beta));
  }
  if (family == WaveletFamily::kMorse && beta / gamma > kMaxMorseBetaOverGamma) {
    return Fail(why, "MorletWavelet.beta / gamma: expected <= " + ToText(kMaxMorseBetaOverGamma) +
                         ", got " + ToText(beta / gamma));
  }
  if (!std::isfinite(omega0) || omega0 <= 0.0) {
    return Fail(why, "MorletWavelet.omega0: expected a finite value > 0, got " + ToText(omega0));
  }
  if (omega0 < kMinOmega0 && !admissibility_correction) {
    return Fail(why, "MorletWavelet.omega0: expected >= " + ToText(kMinOmega0) +
                         " (or admissibility_correction = true), got " + ToText(omega0));
  }
  if (omega0 < kMinCorrectedOmega0) {
    return Fail(why, "MorletWavelet.omega0: expected >= " + ToText(kMinCorrectedOmega0) +
                         " with admissibility_correction, got " + ToText(omega0));
  }
  if (omega0 > kMaxOmega0) {
    return Fail(
        why, "MorletWavelet.omega0: expected <= " + ToText(kMaxOmega0) + ", got " + ToText(omega0));
  }
  return true;
}

namespace {

// log(psi^(u) / psi^(u_p)) of the Morse wavelet: beta ln(u / u_p) - u^gamma + beta / gamma.
double MorseLogRatio(double gamma, double beta, double u) {
  const double up = std::pow(beta / gamma, 1.0 / gamma);
  return beta * std::log(u / up) - std::pow(u, gamma) + beta / gamma;
}

// K of the Morse wavelet with the normalisation, times a (so psi^ = this * exp(log ratio)).
double MorsePeak(const MorletWavelet& w) {
  if (w.normalisation == Normalisation::kAmplitude) return 2.0;
  // K^2 a^2 = 2 pi gamma 2^r / Gamma(r), r = (2 beta + 1) / gamma, and psi^(u_p) = K.
  const double r = (2.0 * w.beta + 1.0) / w.gamma;
  const double up = std::pow(w.beta / w.gamma, 1.0 / w.gamma);
  const double log_ka2 = std::log(2.0 * kPi * w.gamma) + r * std::log(2.0) - std::lgamma(r);
  // psi^(u_p) = K a u_p^beta exp(-u_p^gamma).
  return std::exp(0.5 * log_ka2 + w.beta * std::log(up) - w.beta / w.gamma);
}

}  // namespace

double MorletWavelet::FourierTransform(double u) const {
  if (family == WaveletFamily::kMorse) {
    if (!(u > 0.0)) return 0.0;
    return MorsePeak(*this) * std::exp(MorseLogRatio(gamma, beta, u));
  }
  const double k = normalisation == Normalisation::kAmplitude
                       ? 2.0                                          // sqrt(2/pi) sqrt(2 pi)
                       : std::sqrt(2.0 * kPi) / std::pow(kPi, 0.25);  // pi^-1/4 sqrt(2 pi)
  const double d = u - omega0;
  double value = std::exp(-0.5 * d * d);
  // exp(-(u - w0)^2 / 2) - exp(-(u^2 + w0^2) / 2) = exp(-(u - w0)^2 / 2) (1 - exp(-u w0)):
  // no cancellation for small u w0.
  if (admissibility_correction) value *= -std::expm1(-u * omega0);
  return k * value;
}

void MorletWavelet::Band(double tolerance, double* lo, double* hi) const {
  if (!(tolerance > 0.0 && tolerance < 1.0)) {
    ThrowInvalid("MorletWavelet::Band: tolerance", "a value in (0, 1)", ToText(tolerance));
  }
  if (lo == nullptr || hi == nullptr) {
    throw std::invalid_argument("MorletWavelet::Band: expected two outputs, got a null pointer");
  }
  ThrowIfInvalid(*this);
  const double log_tolerance = std::log(tolerance);
  if (family == WaveletFamily::kMorlet) {
    const double radius = std::sqrt(-2.0 * log_tolerance);
    // The correction term exp(-(u^2 + omega0^2) / 2) exceeds the tolerance for
    // |u| < sqrt(radius^2 - omega0^2): keep those u too.
    *lo = std::min(omega0 - radius,
                   admissibility_correction
                       ? -std::sqrt(std::max(0.0, radius * radius - omega0 * omega0))
                       : 0.0);
    *hi = omega0 + radius;
    return;
  }
  // The log ratio rises to 0 at u_p and falls on both sides: bisect each side.
  const double up = std::pow(beta / gamma, 1.0 / gamma);
  const auto below = [&](double u) { return MorseLogRatio(gamma, beta, u) < log_tolerance; };
  double a = up, b = up;
  while (!below(a) && a > 1e-300) a *= 0.5;
  while (!below(b)) b *= 2.0;
  double l0 = a, l1 = up, h0 = up, h1 = b;
  for (int i = 0; i < 200; ++i) {
    const double lm = 0.5 * (l0 + l1), hm = 0.5 * (h0 + h1);
    (below(lm) ? l0 : l1) = lm;
    (below(hm) ? h1 : h0) = hm;
  }
  *lo = l0;
  *hi = h1;
}

double MorletWavelet::TimeSpread() const {
  ThrowIfInvalid(*this);
  if (family == WaveletFamily::kMorlet && !admissibility_correction) return std::sqrt(0.5);
  // sigma_t^2 = integral psi^'(u)^2 du / integral psi^(u)^2 du by the
  // trapezoid rule over the band (1e-12 of the peak), 20000 panels;
  // psi^' by central differences.
  double lo = 0.0, hi = 0.0;
  Band(1e-12, &lo, &hi);
  const int panels = 20000;
  const double h = (hi - lo) / panels;
  double num = 0.0, den = 0.0;
  for (int i = 0; i <= panels; ++i) {
    const double u = lo + h * i;
    const double weight = (i == 0 || i == panels) ? 0.5 : 1.0;
    const double value = FourierTransform(u);
    const double slope = (FourierTransform(u + 1e-4 * h) - FourierTransform(u - 1e-4 * h)) /
                         (2e-4 * h);
    num += weight * slope * slope;
    den += weight * value * value;
  }
  return std::sqrt(num / den);
}

double MorletWavelet::ConeOfInfluenceTime_s(double scale_s) const {
  return 2.0 * TimeSpread() * scale_s;
}

std::string MorletWavelet::Describe() const {
  if (family == WaveletFamily::kMorse) {
    return "Morse gamma " + ToText(gamma) + " beta " + ToText(beta);
  }
  return "Morlet omega0 " + ToText(omega0);
}

double MorletWavelet::RidgeAngularFrequency() const {
  const bool energy = normalisation == Normalisation::kEnergy;
  if (family == WaveletFamily::kMorse) {
    // d/du [(beta + n) ln u - u^gamma] = 0, n = 0 (L1) or 1/2 (L2).
    return std::pow((beta + (energy ? 0.5 : 0.0)) / gamma, 1.0 / gamma);
  }
  if (!admissibility_correction) {
    return energy ? 0.5 * (omega0 + std::sqrt(omega0 * omega0 + 2.0)) : omega0;
  }
  // Checked here only, before the bisection (NaN would fail its bracket
  // check): the closed forms above run per ridge sample (UnitCosineMagnitude)
  // on wavelets their callers have checked.
  ThrowIfInvalid(*this);
  // d/du log(n(u) psi^(u)) = 0, n(u) = 1 or sqrt(u); the root is bracketed
  // near omega0 and the derivative decreases through it: bisect to rounding.
  // With psi^ = g (1 - e^(-u w0)), g = exp(-(u - w0)^2 / 2), the log's slope
  // is w0 / e - u, e = 1 - exp(-u w0): no ratio of two underflowing
  // exponentials (g and its correction reached 0 from omega0 77.5 on).
  const auto slope = [&](double u) {
    return omega0 / -std::expm1(-u * omega0) - u + (energy ? 0.5 / u : 0.0);
  };
  double lo = std::max(1e-3, 0.5 * omega0), hi = omega0 + 2.0;
  PODID_CHECK(slope(lo) > 0.0 && slope(hi) < 0.0);
  for (int i = 0; i < 200 && hi - lo > 4e-16 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (slope(mid) > 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double MorletWavelet::PeakAngularFrequency() const {
  MorletWavelet amplitude = *this;
  amplitude.normalisation = Normalisation::kAmplitude;
  return amplitude.RidgeAngularFrequency();
}

double MorletWavelet::ScaleFrequencyConstant() const {
  return convention == ScaleConvention::kRidge ? RidgeAngularFrequency() : PeakAngularFrequency();
}

double MorletWavelet::ScaleToFrequency_Hz(double scale_s) const {
  return ScaleFrequencyConstant() / (2.0 * kPi * scale_s);
}

double MorletWavelet::FrequencyToScale_s(double frequency_Hz) const {
  return ScaleFrequencyConstant() / (2.0 * kPi * frequency_Hz);
}

double MorletWavelet::UnitCosineMagnitude(double scale_s) const {
  const double n = normalisation == Normalisation::kAmplitude ? 1.0 : std::sqrt(scale_s);
  return 0.5 * n * FourierTransform(RidgeAngularFrequency());
}

double MorletWavelet::ConeOfInfluence_s(double scale_s) { return std::sqrt(2.0) * scale_s; }

// ---------------------------------------------------------------- FrequencyGrid

FrequencyGrid FrequencyGrid::Log(double min_Hz, double max_Hz, int voices_per_octave) {
  FrequencyGrid grid;
  grid.min_frequency_Hz = min_Hz;
  grid.max_frequency_Hz = max_Hz;
  grid.spacing = FrequencySpacing::kLog;
  grid.voices_per_octave = voices_per_octave;
  return grid;
}

FrequencyGrid FrequencyGrid::Linear(double min_Hz, double max_Hz, int bins) {
  FrequencyGrid grid;
  grid.min_frequency_Hz = min_Hz;
  grid.max_frequency_Hz = max_Hz;
  grid.spacing = FrequencySpacing::kLinear;
  grid.bins = bins;
  return grid;
}

bool FrequencyGrid::IsValid(std::string* why) const {
  if (spacing != FrequencySpacing::kLog && spacing != FrequencySpacing::kLinear) {
    return Fail(why, "FrequencyGrid.spacing: expected kLog or kLinear, got " +
                         ToText(static_cast<int>(spacing)));
  }
  if (!std::isfinite(min_frequency_Hz) || min_frequency_Hz <= 0.0) {
    return Fail(why, "FrequencyGrid.min_frequency_Hz: expected a finite value > 0, got " +
                         ToText(min_frequency_Hz));
  }
  if (!std::isfinite(max_frequency_Hz) || max_frequency_Hz <= min_frequency_Hz) {
    return Fail(why,
                "FrequencyGrid.max_frequency_Hz: expected a finite value > min_frequency_Hz (" +
                    ToText(min_frequency_Hz) + "), got " + ToText(max_frequency_Hz));
  }
  if (spacing == FrequencySpacing::kLog &&
      (voices_per_octave < 1 || voices_per_octave > kMaxVoicesPerOctave)) {
    return Fail(why, "FrequencyGrid.voices_per_octave: expected 1.." + ToText(kMaxVoicesPerOctave) +
                         ", got " + ToText(voices_per_octave));
  }
  if (spacing == FrequencySpacing::kLinear && (bins < kMinLinearBins || bins > kMaxFrequencies)) {
    return Fail(why, "FrequencyGrid.bins: expected " + ToText(kMinLinearBins) + ".." +
                         ToText(kMaxFrequencies) + ", got " + ToText(bins));
  }
  if (spacing == FrequencySpacing::kLog) {
    // A subnormal minimum overflows the ratio: the count would read "inf".
    const double ratio = max_frequency_Hz / min_frequency_Hz;
    if (!std::isfinite(ratio)) {
      return Fail(
          why, "FrequencyGrid: expected a finite ratio max_frequency_Hz / min_frequency_Hz, got " +
                   ToText(max_frequency_Hz) + " / " + ToText(min_frequency_Hz));
    }
    // Frequencies_Hz()'s own count: floor(v log2(ratio)) + 1.
    const double count = std::floor(voices_per_octave * std::log2(ratio) + 1e-9) + 1.0;
    if (count > kMaxFrequencies) {
      return Fail(why, "FrequencyGrid: expected at most " + ToText(kMaxFrequencies) +
                           " frequencies, got " + ToText(count));
    }
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

}  // namespace podid::wavelet
