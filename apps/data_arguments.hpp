#pragma once
// The options every command that reads a data file takes (docs/cli.md, "Data
// files"): --variable, --channels, --rate / --step, and the conditioning
// options --window, --detrend, --lowpass / --highpass / --bandpass,
// --filter-order, --decimate (podid/core/conditioning.hpp).

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "podid/core/conditioning.hpp"
#include "podid/core/io.hpp"

namespace podid::cli {

struct DataArguments {
  std::string variable;
  std::string channels;  ///< comma-separated names
  double rate_Hz = 0.0;
  double step_s = 0.0;
  std::string window;   ///< "START:END" (s)
  std::string detrend;  ///< none | constant | linear
  double lowpass_Hz = 0.0;
  double highpass_Hz = 0.0;
  std::string bandpass;  ///< "LOW:HIGH" (Hz)
  int filter_order = 4;
  int decimate = 1;

  /// Adds the options (`prefix` before each long name).
  void AddTo(CLI::App& command, const std::string& prefix = "");
  /// The DataReadOptions these give (throws std::invalid_argument).
  DataReadOptions Options() const;
  /// The conditioning these give (throws std::invalid_argument).
  ConditioningOptions Conditioning() const;
  /// Reads `path` with them (the channels chosen and ordered); prints the
  /// reader's notes on stderr as "podid: note: ...". No conditioning.
  TimeSeries Read(const std::string& path) const;
  /// Read() then ConditionRecord() with Conditioning().
  TimeSeries ReadConditioned(const std::string& path) const;
  /// The same choices as case-file keys for `--set` (data.file = `path` made
  /// absolute, data.variable, data.channels, data.rate, data.window, ...):
  /// identify and landscape pass the command line to the case this way, so
  /// the measured and the simulated signals are conditioned alike. Refuses
  /// --decimate (the simulation runs on the measured grid).
  std::vector<std::string> CaseSets(const std::string& path) const;
  /// The first of these options given on the command line ("--decimate"), or
  /// "" for none: plan refuses them without a DATA file to apply them to.
  std::string FirstGiven() const;

 private:
  std::vector<std::string> ChannelList() const;
  CLI::Option* channels_option_ = nullptr;
  CLI::Option* rate_option_ = nullptr;
  CLI::Option* step_option_ = nullptr;
  CLI::Option* lowpass_option_ = nullptr;
  CLI::Option* highpass_option_ = nullptr;
  CLI::Option* bandpass_option_ = nullptr;
  CLI::Option* order_option_ = nullptr;
  std::vector<const CLI::Option*> added_;  // every option AddTo added, in order
  std::string prefix_;
};

}  // namespace podid::cli
