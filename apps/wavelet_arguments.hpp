#pragma once
// The wavelet options `podid cwt` takes and the wavelet term of `podid
// identify` and `podid landscape` shares: --wavelet, --omega0, --gamma, --beta.

#include <CLI/CLI.hpp>
#include <string>

#include "podid/wavelet/cwt.hpp"

namespace podid::cli {

struct WaveletArguments {
  std::string family = "morlet";
  double omega0 = 6.0;
  double gamma = 3.0;
  double beta = 20.0;

  /// Adds the four options; `what` ends --wavelet's help ("" or " of the wavelet term").
  void AddTo(CLI::App& command, const std::string& what = "");
  /// Sets the family and its parameters in *wavelet (normalisation and
  /// convention are left alone). Throws std::invalid_argument naming the
  /// option: an unknown family, or a wavelet MorletWavelet::IsValid refuses
  /// (Morlet omega0 < 5 without correction, Morse beta / gamma > 100).
  void ApplyTo(wavelet::MorletWavelet* wavelet) const;
};

}  // namespace podid::cli
