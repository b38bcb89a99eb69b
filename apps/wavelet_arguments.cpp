#include "wavelet_arguments.hpp"

#include <stdexcept>

#include "cli_common.hpp"
#include "podid/core/error.hpp"

namespace podid::cli {

void WaveletArguments::AddTo(CLI::App& command, const std::string& what) {
  command
      .add_option("--wavelet", family,
                  "morlet or morse (generalised Morse, MATLAB's default)" + what)
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
}

void WaveletArguments::ApplyTo(wavelet::MorletWavelet* wavelet) const {
  if (family != "morlet" && family != "morse")
    ThrowInvalid("--wavelet", "one of morlet, morse", Excerpt(family));
  wavelet->family = wavelet::ParseWaveletFamily(family);
  wavelet->omega0 = omega0;
  wavelet->gamma = gamma;
  wavelet->beta = beta;
  std::string why;
  if (!wavelet->IsValid(&why)) {
    throw std::invalid_argument(wavelet->family == wavelet::WaveletFamily::kMorlet
                                    ? "--omega0: " + why
                                    : "--gamma/--beta: " + why);
  }
}

}  // namespace podid::cli
