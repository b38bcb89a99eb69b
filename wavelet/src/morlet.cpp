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

}  // namespace podid::wavelet
