#pragma once
// The pieces of the `podid._podid` extension, one file per podid module.
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "podid/core/case_file.hpp"
#include "podid/wavelet/cwt.hpp"

namespace podid::python {

void BindPod(pybind11::module_& m);
void BindWavelet(pybind11::module_& m);
void BindModel(pybind11::module_& m);
void BindIdent(pybind11::module_& m);

/// The library's field names in a message (FrequencyGrid.min_frequency_Hz,
/// MorletWavelet.beta) as the module's keyword arguments (fmin, beta), which
/// the caller typed (bind_wavelet.cpp).
std::string PythonNames(std::string message);

/// The wavelet's keywords (the CLI's --wavelet, --omega0, --gamma, --beta,
/// --normalisation, --scale-convention), shared by the wavelet functions and
/// the objective's IF term.
struct WaveletArguments {
  std::string family;
  double omega0, gamma, beta;
  std::string normalisation, convention;
};

/// The wavelet they name; throws std::invalid_argument (a ValueError) in
/// the keywords' names: an unknown name, or what MorletWavelet::IsValid
/// refuses (bind_wavelet.cpp).
wavelet::MorletWavelet MakeWavelet(const WaveletArguments& w);

/// A case-file path, or TOML text when `case_` holds a newline, with
/// `--set`-style "key=value" overrides (module.cpp).
CaseDocument LoadCase(const std::string& case_, const std::vector<std::string>& set);

}  // namespace podid::python
