#pragma once
// Helpers shared by the podid subcommands.

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "podid/core/case_file.hpp"

namespace podid::cli {

/// The case file and `--set key=value` overrides most commands take.
struct CaseArguments {
  std::string path;
  std::vector<std::string> sets;

  /// Adds the positional CASE.toml and the repeatable --set option.
  void AddTo(CLI::App& command);
  /// Loads the case and applies the overrides (throws std::invalid_argument).
  CaseDocument Load() const;
};

/// The default output path: `<stem of input><suffix>` in the current folder.
std::string DefaultOutput(const std::string& input, const std::string& suffix);

}  // namespace podid::cli
