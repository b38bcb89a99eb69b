#pragma once
// Options shared by `podid identify` and `podid landscape`: the measured data,
// the objective's settings and the parameters' starts.

#include <CLI/CLI.hpp>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <utility>
#include <vector>

#include "cli_common.hpp"
#include "data_arguments.hpp"
#include "podid/ident/objective.hpp"
#include "wavelet_arguments.hpp"

namespace podid::cli {

struct ObjectiveArguments {
  CaseArguments input;
  std::string measured;            ///< -m; empty: the case's [data] file
  DataArguments measured_reading;  ///< --variable, --channels, --rate, --step, conditioning of -m
  int modes = 1;
  bool raw_sigma = false;
  bool keep_mean = false;
  bool noise_sigma = false;
  bool no_noise_sigma = false;
  std::vector<std::string> mode_bands;  ///< K=LOW:HIGH
  double ridge_snr = 3.0;
  double min_signal = 0.1;
  double fmin_Hz = 10.0;
  double fmax_Hz = 120.0;
  double penalty_s = 0.05;
  WaveletArguments wavelet;         ///< the wavelet term's wavelet: cwt's wavelet options
  /// The options only the IF term reads (--fmin, --fmax, --penalty,
  /// --mode-band, --ridge-snr and the wavelet's): refused without it.
  std::vector<const CLI::Option*> ridge_options;
  std::vector<std::string> starts;  ///< name=value
  /// The ridge's CwtOptions::threads (not an option: identify gives a single
  /// start two threads, see cmd_identify.cpp).
  int ridge_threads = 1;

  void AddTo(CLI::App& command);
  /// Passes -m and the data options to the case as `--set data.*` keys (so
  /// the case's [force] channel and conditioning see them). Call first.
  void PrepareData();
  /// Loads case and data and builds the objective with `weightings` (one
  /// simulation serves them all; prints its notes on stderr).
  std::unique_ptr<ident::ObjectiveFunction> Build(std::vector<ident::NamedObjective> weightings) const;
  /// The start vector after --start overrides (throws for unknown names).
  Eigen::VectorXd Start(const ident::ObjectiveFunction& objective) const;
  /// --start's name=value pairs; throws std::invalid_argument naming --start
  /// for a missing '=' or a name given twice.
  std::vector<std::pair<std::string, std::string>> StartPairs() const;
};

/// The wavelet term's settings per compared mode, as the objective resolved
/// them (a mode's band follows its spectral peak unless --mode-band): each
/// mode's band, wavelet, normalisation, scale convention, penalty and the
/// ridge samples compared. An empty array without a wavelet term. The
/// "ridges" of identify's and landscape's --json.
nlohmann::json RidgesJson(const ident::ObjectiveFunction& objective);

/// `--objective` presets, or `--terms`/`--weights`.
ident::ObjectiveWeights WeightsFrom(const std::string& objective, const std::string& terms,
                                    const std::string& weights);

}  // namespace podid::cli
