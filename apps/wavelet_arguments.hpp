#pragma once
// The wavelet options `podid cwt` and `podid plan` take and the wavelet term
// of `podid identify` and `podid landscape` shares: --wavelet, --omega0,
// --gamma, --beta, --normalisation, --scale-convention; and the analysis grid
// of cwt and plan: --fmin, --fmax, --voices, --bins.

#include <CLI/CLI.hpp>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "podid/wavelet/cwt.hpp"

namespace podid::cli {

/// The library's parse of a name, its message naming the option ("--padding:
/// expected one of reflect, zero, periodic, got ...") instead of its field.
template <typename Parse>
auto ParseOption(const char* option, const std::string& text, Parse parse) {
  try {
    return parse(text);
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    const std::size_t colon = message.find(": ");
    throw std::invalid_argument(
        option + (colon == std::string::npos ? ": " + message : message.substr(colon)));
  }
}

struct WaveletArguments {
  std::string family = "morlet";
  double omega0 = 6.0;
  double gamma = 3.0;
  double beta = 20.0;
  std::string normalisation = "amplitude";
  std::string convention = "ridge";
  /// The options, once added: what was given (count() > 0).
  std::vector<const CLI::Option*> options;

  /// Adds the options; `what` follows "Wavelet" in --wavelet's help ("" or " of the wavelet term").
  void AddTo(CLI::App& command, const std::string& what = "");
  /// Sets *wavelet from them. Throws std::invalid_argument naming the
  /// option: an unknown name, --omega0 given with Morse or --gamma/--beta with
  /// Morlet (it had no effect), or a wavelet MorletWavelet::IsValid refuses
  /// (Morse beta / gamma > 100; the bounds of each number CLI11 checks).
  void ApplyTo(wavelet::MorletWavelet* wavelet) const;
};

/// Throws std::invalid_argument naming `where` unless fmin_Hz .. fmax_Hz holds
/// at least two frequencies of a log grid of `voices` per octave: one
/// frequency is no grid (the ridge's refinement, the inverse and the
/// synchrosqueezing need neighbours; podid cwt refused it, identify did not).
void CheckTwoFrequencies(const std::string& where, double fmin_Hz, double fmax_Hz, int voices);

/// --fmin and --fmax as a band: throws std::invalid_argument naming --fmin
/// when fmax_Hz is not above fmin_Hz (the library's check would name
/// FrequencyGrid.max_frequency_Hz). `cap` names what fmax_Hz is when it is
/// not --fmax (e.g. "the Nyquist frequency"), or is empty.
void CheckBand(double fmin_Hz, double fmax_Hz, const std::string& cap = "");

/// The analysis grid of `podid cwt` and `podid plan`: --fmin, --fmax and
/// --voices (log) or --bins (linear), each checked against the library's bounds
/// (kMaxVoicesPerOctave, kMinLinearBins, kMaxFrequencies) under its own name.
struct GridArguments {
  double fmin_Hz = 10.0;
  double fmax_Hz = 120.0;
  int voices = 32;
  std::optional<int> bins;

  /// Adds the four options; `fmax_help` is --fmax's help line.
  void AddTo(CLI::App& command, const std::string& fmax_help);
  /// The grid over --fmin .. min(--fmax, cap_Hz) (`cap` names cap_Hz in a
  /// message, e.g. "the Nyquist frequency"). Throws std::invalid_argument naming
  /// the options for a band that is empty or holds more than kMaxFrequencies
  /// frequencies.
  wavelet::FrequencyGrid Grid(double cap_Hz = std::numeric_limits<double>::infinity(),
                              const std::string& cap = "") const;
};

}  // namespace podid::cli
