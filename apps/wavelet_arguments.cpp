#include "wavelet_arguments.hpp"

#include <stdexcept>
#include <string>

#include "cli_common.hpp"

namespace podid::cli {
namespace {

// The library's parse of a name, its message naming the option ("--wavelet:
// expected one of morlet, morse, got ...") instead of the field.
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

}  // namespace

void WaveletArguments::AddTo(CLI::App& command, const std::string& what) {
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
  std::string why;
  if (!wavelet->IsValid(&why)) {
    throw std::invalid_argument(wavelet->family == wavelet::WaveletFamily::kMorlet
                                    ? "--omega0: " + why
                                    : "--gamma/--beta: " + why);
  }
}

}  // namespace podid::cli
