#pragma once
// Case files: TOML documents in the schema of docs/case-file.md (example:
// examples/beam.toml). A CaseDocument holds the parsed document, accepts
// `--set key=value` overrides and numeric updates, and turns into a validated
// CaseSpec. toml++ stays private to case_file.cpp.
//
// Keys are dotted paths; array elements are addressed by their 0-based index:
//   beam.length, nonlinearity.0.k3, damping.modal_ratios.1,
//   identify.parameter.0.start
//
// Errors are std::invalid_argument messages of the form
//   "<file>:<line>: <key>: expected <what>, got <value>"
// where the location is "--set <key>=<value>" for a value set from outside.

#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "podid/core/case_spec.hpp"

namespace podid {

class CaseDocument {
 public:
  /// Reads and parses a case file. Relative paths in it (force.file) are
  /// resolved against the file's folder.
  static CaseDocument Load(const std::string& path);
  /// Parses TOML text. `source_name` is used in messages; relative paths in
  /// the document are resolved against `base_directory` (default: the
  /// current directory).
  static CaseDocument Parse(std::string_view text,
                            std::string source_name,
                            std::string base_directory = {});

  CaseDocument(const CaseDocument& other);
  CaseDocument& operator=(const CaseDocument& other);
  CaseDocument(CaseDocument&& other) noexcept;
  CaseDocument& operator=(CaseDocument&& other) noexcept;
  ~CaseDocument();

  /// `--set key=value`: `value_text` is a TOML value (`2.5e9`, `[1, 2]`,
  /// `"gap"`); a bare word is taken as a string where the schema expects a
  /// string (`force.type=harmonic`). The key must be in the schema; it need
  /// not be in the document (missing tables are created, and an array index
  /// equal to the array's length appends). The value is checked by ToSpec().
  void Set(std::string_view key, std::string_view value_text);

  /// Sets a real-valued key (a key IsNumericKey() accepts) to `value`. Used by
  /// the identification on every evaluation: no parsing of TOML, no I/O.
  /// Distinct copies may be used from distinct threads.
  void SetNumber(std::string_view key, double value);

  /// The number at `key` (an integer or a float of the document).
  /// Throws std::invalid_argument when the key is missing or not a number.
  double GetNumber(std::string_view key) const;

  /// True when `key` is present in the document.
  bool Has(std::string_view key) const;

  /// The full validation: every key known, every type and range right, the
  /// force file read. Throws std::invalid_argument on the first problem.
  CaseSpec ToSpec() const;

  /// The name used in messages (the path given to Load, or Parse's name).
  const std::string& source_name() const;

  /// True when `key` is a real-valued key of the schema (with array indices,
  /// e.g. "nonlinearity.0.k3", "initial.displacement.3"): the keys an
  /// identification parameter may set. Integer keys (elements, node, seed) and
  /// strings are not.
  static bool IsNumericKey(std::string_view key);

  struct Impl;  ///< opaque: the parsed document (toml++ stays in case_file.cpp)

 private:
  explicit CaseDocument(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

/// Splits each `key=value` argument at its first '='. Throws
/// std::invalid_argument("--set <arg>: expected key=value (e.g. time.duration=1.0),
/// got ...") when the
/// '=' is missing or the key is empty.
std::vector<std::pair<std::string, std::string>> ParseSetArguments(
    const std::vector<std::string>& arguments);

/// Applies ParseSetArguments(arguments) to `document`, in order.
void ApplySetArguments(CaseDocument& document, const std::vector<std::string>& arguments);

/// A TOML basic string holding `text` (quotes and backslashes escaped, control
/// characters as \uXXXX): a value for CaseDocument::Set, e.g. a file path.
std::string TomlString(std::string_view text);

}  // namespace podid
