#pragma once
// The wavelet options `podid cwt` and `podid plan` take and the wavelet term
// of `podid identify` and `podid landscape` shares: --wavelet, --omega0,
// --gamma, --beta, --normalisation, --scale-convention.

#include <CLI/CLI.hpp>
#include <string>

#include "podid/wavelet/cwt.hpp"

namespace podid::cli {

struct WaveletArguments {
  std::string family = "morlet";
  double omega0 = 6.0;
  double gamma = 3.0;
  double beta = 20.0;
  std::string normalisation = "amplitude";
  std::string convention = "ridge";

  /// Adds the options; `what` follows "Wavelet" in --wavelet's help ("" or " of the wavelet term").
  void AddTo(CLI::App& command, const std::string& what = "");
  /// Sets *wavelet from them. Throws std::invalid_argument naming the
  /// option: an unknown name, or a wavelet MorletWavelet::IsValid refuses
  /// (Morse beta / gamma > 100; the bounds of each number CLI11 checks).
  void ApplyTo(wavelet::MorletWavelet* wavelet) const;
};

}  // namespace podid::cli
