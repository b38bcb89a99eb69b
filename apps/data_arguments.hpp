#pragma once
// The options every command that reads a data file takes (docs/cli.md, "Data
// files"): --variable, --channels, --rate / --step.

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "podid/core/io.hpp"

namespace podid::cli {

struct DataArguments {
  std::string variable;
  std::string channels;  ///< comma-separated names
  double rate_Hz = 0.0;
  double step_s = 0.0;

  /// Adds --variable, --channels, --rate and --step (`prefix` before each
  /// long name, e.g. "measured-" for identify's --measured-channels).
  void AddTo(CLI::App& command, const std::string& prefix = "");
  /// The DataReadOptions these give (throws std::invalid_argument).
  DataReadOptions Options() const;
  /// Reads `path` with them; prints the reader's notes on stderr as
  /// "podid: note: ...".
  TimeSeries Read(const std::string& path) const;

 private:
  CLI::Option* rate_option_ = nullptr;
  CLI::Option* step_option_ = nullptr;
};

}  // namespace podid::cli
