#include "wavelet_arguments.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "cli_common.hpp"
#include "podid/core/error.hpp"

namespace podid::cli {
void WaveletArguments::AddTo(CLI::App& command, const std::string& what) {
  options.clear();
  command
      .add_option("--wavelet", family,
                  "Wavelet" + what + ": morlet or morse (generalised Morse, MATLAB's default)")
      ->capture_default_str();
  command.add_option("--omega0", omega0, "Morlet centre frequency")
      ->capture_default_str()
      ->check(NumberIn({wavelet::kMinOmega0}, {wavelet::kMaxOmega0}));
  command.add_option("--gamma", gamma, "Morse symmetry gamma")
      ->capture_default_str()
      ->check(NumberIn({wavelet::kMinMorseGamma}, {wavelet::kMaxMorseGamma}));
  command.add_option("--beta", beta, "Morse decay beta (beta/gamma <= 100)")
      ->capture_default_str()
      ->check(NumberIn({wavelet::kMinMorseBeta}, {wavelet::kMaxMorseBeta}));
  command.add_option("--normalisation", normalisation, "amplitude (L1) or energy (L2)")
      ->capture_default_str();
  command
      .add_option("--scale-convention", convention,
                  "Frequency of a scale: ridge (Torrence & Compo: where a tone peaks) or\n"
                  "peak (MATLAB, PyWavelets: the wavelet's centre frequency); they differ\n"
                  "only with --normalisation energy (1.35 % for Morlet omega0 6)")
      ->capture_default_str();
  for (const char* name :
       {"--wavelet", "--omega0", "--gamma", "--beta", "--normalisation", "--scale-convention"}) {
    options.push_back(command.get_option(name));
  }
}

void WaveletArguments::ApplyTo(wavelet::MorletWavelet* wavelet) const {
  wavelet->family = ParseOption("--wavelet", family, wavelet::ParseWaveletFamily);
  wavelet->omega0 = omega0;
  wavelet->gamma = gamma;
  wavelet->beta = beta;
  wavelet->normalisation =
      ParseOption("--normalisation", normalisation, wavelet::ParseNormalisation);
  wavelet->convention =
      ParseOption("--scale-convention", convention, wavelet::ParseScaleConvention);
  // A parameter of the other family changed nothing: say so.
  const bool morse = wavelet->family == wavelet::WaveletFamily::kMorse;
  for (const CLI::Option* option : options) {
    const std::string name = option->get_name();
    const bool morlet_only = name == "--omega0", morse_only = name == "--gamma" || name == "--beta";
    if (option->count() > 0 && ((morse && morlet_only) || (!morse && morse_only))) {
      ThrowInvalid(name,
                   std::string("--wavelet ") + (morse ? "morlet" : "morse") + " with it (" +
                       (morse ? "the Morlet wavelet's" : "a Morse wavelet's") + " parameter)",
                   std::string("--wavelet ") + (morse ? "morse" : "morlet"));
    }
  }
  if (wavelet->family == wavelet::WaveletFamily::kMorse &&
      beta / gamma > wavelet::kMaxMorseBetaOverGamma) {
    // Each is within its own range (CLI11 checked): name the ratio, not the
    // library's field.
    ThrowInvalid(
        "--beta",
        "at most " + ToText(wavelet::kMaxMorseBetaOverGamma) + " x --gamma (" + ToText(gamma) + ")",
        ToText(beta));
  }
  std::string why;
  if (!wavelet->IsValid(&why)) {
    throw std::invalid_argument(wavelet->family == wavelet::WaveletFamily::kMorlet
                                    ? "--omega0: " + why
                                    : "--gamma/--beta: " + why);
  }
}

void CheckBand(double fmin_Hz, double fmax_Hz, const std::string& cap) {
  if (fmax_Hz > fmin_Hz) return;
  if (cap.empty()) {
    ThrowInvalid("--fmin", "a frequency below --fmax (" + ToText(fmax_Hz) + " Hz)",
                 ToText(fmin_Hz) + " Hz");
  }
  ThrowInvalid("--fmin", "a frequency below " + cap + " (" + ToText(fmax_Hz) + " Hz)",
               ToText(fmin_Hz) + " Hz");
}

void CheckTwoFrequencies(const std::string& where, double fmin_Hz, double fmax_Hz, int voices) {
  const wavelet::FrequencyGrid grid = wavelet::FrequencyGrid::Log(fmin_Hz, fmax_Hz, voices);
  if (std::string why; grid.IsValid(&why) && grid.Frequencies_Hz().size() < 2) {
    ThrowInvalid(where,
                 "a band of at least 2 frequencies, one step of the grid (1/" + ToText(voices) +
                     " octave: an upper frequency of at least " +
                     ToText(fmin_Hz * std::exp2(1.0 / voices)) + " Hz)",
                 ToText(std::log2(fmax_Hz / fmin_Hz)) + " octaves, 1 frequency");
  }
}

void GridArguments::AddTo(CLI::App& command, const std::string& fmax_help) {
  command.add_option("--fmin", fmin_Hz, "Lowest analysis frequency (Hz)")
      ->capture_default_str()
      ->check(NumberIn({0.0, true}));
  command.add_option("--fmax", fmax_Hz, fmax_help)
      ->capture_default_str()
      ->check(NumberIn({0.0, true}));
  auto* log = command.add_option("--voices", voices, "Log grid: frequencies per octave")
                  ->capture_default_str()
                  ->check(IntegerIn(1, wavelet::kMaxVoicesPerOctave));
  auto* linear = command.add_option("--bins", bins, "Linear grid of this many frequencies")
                     ->check(IntegerIn(wavelet::kMinLinearBins, wavelet::kMaxFrequencies));
  log->excludes(linear);
  linear->excludes(log);
}

wavelet::FrequencyGrid GridArguments::Grid(double cap_Hz, const std::string& cap) const {
  const double top_Hz = std::min(fmax_Hz, cap_Hz);
  CheckBand(fmin_Hz, top_Hz, top_Hz < fmax_Hz ? cap : "");
  if (bins) return wavelet::FrequencyGrid::Linear(fmin_Hz, top_Hz, *bins);
  // The log grid's count, as FrequencyGrid::IsValid bounds it.
  const double count = voices * std::log2(top_Hz / fmin_Hz);
  if (!(count <= wavelet::kMaxFrequencies)) {
    ThrowInvalid(
        "--voices/--fmin/--fmax",
        "at most " + ToText(wavelet::kMaxFrequencies) + " frequencies (--voices x octaves)",
        ToText(voices) + " x " + ToText(std::log2(top_Hz / fmin_Hz)) + " octaves");
  }
  // The library's errors would name its scalogram instead of these options.
  CheckTwoFrequencies("--fmin/--fmax/--voices", fmin_Hz, top_Hz, voices);
  return wavelet::FrequencyGrid::Log(fmin_Hz, top_Hz, voices);
}

}  // namespace podid::cli
