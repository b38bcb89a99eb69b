#pragma once
// Helpers shared by the podid subcommands.

#include <CLI/CLI.hpp>
#include <limits>
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

/// Upper bounds of integer options (docs/cli.md), checked by CLI11 before
/// anything runs. Generous: the real limits (a model's dofs, a file's
/// channels) are checked once known; these only stop an absurd number early.
inline constexpr long long kMaxModesPrinted = 1'000'000;    ///< modes --count
inline constexpr long long kMaxPodModesOption = 1'000'000;  ///< pod --modes
inline constexpr long long kMaxPomOption = 1'000'000;       ///< cwt --pom
inline constexpr long long kMaxObjectiveModes = 1'000;      ///< identify/landscape --modes

/// The default output path: `<stem of input><suffix>` in the current folder.
std::string DefaultOutput(const std::string& input, const std::string& suffix);

/// A file a command reads or writes, with what named it (for messages):
/// {"-o", "out.csv"}, {"case file", "beam.toml"}.
struct NamedFile {
  std::string what;
  std::string path;
};

/// The files a case makes a command read: the case file and its [force] file
/// (after the --set overrides). Throws std::invalid_argument for a bad case.
std::vector<NamedFile> CaseInputFiles(const CaseArguments& arguments);

/// Run by every command before it computes anything. Each output (empty
/// paths, options not given, are skipped: NonEmptyPath refuses a given empty
/// one) must be writable as WriteFileAtomically will write it
/// (its folder exists and is writable, it is not a folder, see ResolveOutput),
/// and must not be the same file as an input or as another output: files are
/// compared by device and inode after following symlinks, so a symlink, a hard
/// link or a "./x" spelling of an input is refused too. Throws
/// std::invalid_argument naming the option and both files (exit status 1).
void CheckOutputs(const std::vector<NamedFile>& inputs, const std::vector<NamedFile>& outputs);

/// For an output folder that is created if missing (identify --plot-dir):
/// it is a writable folder, or its nearest existing ancestor is one. Throws
/// std::invalid_argument.
void CheckOutputFolder(const NamedFile& folder);

/// A CLI11 check for an output option's path: not empty. An empty path would
/// otherwise read as "option not given" (every command skips empty outputs),
/// so `-o ''` wrote nothing and exited 0. `what` is e.g. "a file path"; the
/// message reads "--plot: expected a file path, got an empty one".
CLI::Validator NonEmptyPath(const std::string& what = "a file path");
/// The same for any text option ("--terms: expected a list of terms ..., got an empty one").
CLI::Validator NonEmpty(const std::string& what);

/// A CLI11 check for an integer option in [lower, upper]; its message reads
/// "expected an integer in [lower, upper], got <text>".
CLI::Validator IntegerIn(long long lower, long long upper);

/// One end of NumberIn's interval: closed unless `open`; an infinite value is
/// no bound.
struct NumberEnd {
  double value;
  bool open = false;
};

/// A CLI11 check for a real option: a finite number in the interval. Its
/// message names the option as IntegerIn's does: "--ridge-snr: expected a
/// number in [0, 1000], got "2000"", "--fmin: expected a finite number > 0,
/// got "nan"" (the library's own check would name its field, e.g.
/// FrequencyGrid.min_frequency_Hz, not the option the user typed).
CLI::Validator NumberIn(NumberEnd lower,
                        NumberEnd upper = {std::numeric_limits<double>::infinity()});

}  // namespace podid::cli
