#pragma once
// The case-file reader's shared machinery (not installed): the parsed
// document, the value rules and the Section accessor that reports
// "<file>:<line>: <key>: expected X, got Y". Used by case_file.cpp (the
// schema, --set, [force], [time], ...) and case_model.cpp (the model tables).

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "podid/core/case_file.hpp"
#include "podid/core/case_spec.hpp"
#include "podid/core/error.hpp"
#include "podid/core/time_series.hpp"

namespace podid {
namespace case_detail {

inline std::string FormatReal(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

inline std::string Describe(const toml::node* node) {
  if (node == nullptr) return "nothing";
  if (const auto* v = node->as_integer()) return std::to_string(v->get());
  if (const auto* v = node->as_floating_point()) return FormatReal(v->get());
  if (const auto* v = node->as_string()) return Excerpt(v->get());  // short, escaped
  if (const auto* v = node->as_boolean()) return v->get() ? "true" : "false";
  if (node->is_array()) return "an array";
  if (node->is_table()) return "a table";
  return "a date/time";
}

/// Allowed range of a real value, printed as "a number > 0 (m)".
struct RealRule {
  double lower = -std::numeric_limits<double>::infinity();
  bool lower_open = false;
  double upper = std::numeric_limits<double>::infinity();
  bool upper_open = false;
  std::string_view unit;

  bool Accepts(double x) const {
    if (!std::isfinite(x)) return false;
    if (lower_open ? !(x > lower) : !(x >= lower)) return false;
    if (upper_open ? !(x < upper) : !(x <= upper)) return false;
    return true;
  }
  std::string Text() const {
    std::string out;
    const bool has_lower = std::isfinite(lower), has_upper = std::isfinite(upper);
    if (has_lower && has_upper) {
      out = "a number in " + std::string(lower_open ? "(" : "[") + FormatReal(lower) + ", " +
            FormatReal(upper) + (upper_open ? ")" : "]");
    } else if (has_lower) {
      out = "a number " + std::string(lower_open ? "> " : ">= ") + FormatReal(lower);
    } else if (has_upper) {
      out = "a number " + std::string(upper_open ? "< " : "<= ") + FormatReal(upper);
    } else {
      out = "a finite number";
    }
    if (!unit.empty()) out += " (" + std::string(unit) + ")";
    return out;
  }
};

inline RealRule Positive(std::string_view unit) { return {0.0, true, RealRule{}.upper, false, unit}; }
inline RealRule NonNegative(std::string_view unit) { return {0.0, false, RealRule{}.upper, false, unit}; }
inline RealRule AnyReal(std::string_view unit) { return RealRule{.unit = unit}; }

struct IntRule {
  long long lower = std::numeric_limits<long long>::min();
  long long upper = std::numeric_limits<long long>::max();
  bool Accepts(long long x) const { return x >= lower && x <= upper; }
  std::string Text() const {
    const bool has_upper = upper != std::numeric_limits<long long>::max();
    if (has_upper)
      return "an integer in [" + std::to_string(lower) + ", " + std::to_string(upper) + "]";
    return "an integer >= " + std::to_string(lower);
  }
};

/// A force file read once per document family (copies share it).
struct ForceFileCache {
  std::mutex mutex;
  std::map<std::string, std::shared_ptr<const TimeSeries>> files;
  /// Imported model matrices ([model] type = "matrices"), by file set.
  std::map<std::string, std::shared_ptr<const ImportedMatrices>> models;
};


}  // namespace case_detail

// ---------------------------------------------------------------------------
struct CaseDocument::Impl {
  toml::table root;
  std::string source;
  std::string base_directory;
  /// Line of each key in the source file (toml++ does not copy source
  /// positions with a node, so they are kept here, shared by copies).
  std::shared_ptr<const std::map<std::string, int>> lines;
  /// Keys whose value came from Set()/SetNumber(), with the text for messages.
  std::map<std::string, std::string, std::less<>> origins;
  std::shared_ptr<case_detail::ForceFileCache> force_files;

  std::string Where(std::string_view key) const;
  [[noreturn]] void Fail(std::string_view key,
                         std::string_view expected,
                         std::string_view got) const {
    ThrowInvalid(Where(key) + ": " + std::string(key), expected, got);
  }
};

namespace case_detail {

/// A table of the document being validated, e.g. "beam" or "nonlinearity.0".
class Section {
 public:
  Section(const CaseDocument::Impl& doc, const toml::table* table, std::string key)
      : doc_(doc), table_(table), key_(std::move(key)) {}

  bool present() const { return table_ != nullptr; }
  const std::string& key() const { return key_; }
  std::string Full(std::string_view name) const { return key_ + "." + std::string(name); }
  bool Has(std::string_view name) const { return Node(name) != nullptr; }
  const toml::node* Node(std::string_view name) const {
    return table_ ? table_->get(name) : nullptr;
  }
  [[noreturn]] void Fail(std::string_view name,
                         std::string_view expected,
                         std::string_view got) const {
    doc_.Fail(Full(name), expected, got);
  }
  [[noreturn]] void FailSection(std::string_view expected, std::string_view got) const {
    doc_.Fail(key_, expected, got);
  }

  std::optional<double> OptionalReal(std::string_view name, const RealRule& rule) const {
    const toml::node* node = Node(name);
    if (node == nullptr) return std::nullopt;
    return RealValue(node, Full(name), rule);
  }
  double Real(std::string_view name, const RealRule& rule) const {
    const auto value = OptionalReal(name, rule);
    if (!value) Fail(name, rule.Text(), "nothing (the key is required)");
    return *value;
  }
  double Real(std::string_view name, const RealRule& rule, double fallback) const {
    return OptionalReal(name, rule).value_or(fallback);
  }

  std::optional<long long> OptionalInteger(std::string_view name, const IntRule& rule) const {
    const toml::node* node = Node(name);
    if (node == nullptr) return std::nullopt;
    return IntegerValue(node, Full(name), rule);
  }
  long long Integer(std::string_view name, const IntRule& rule) const {
    const auto value = OptionalInteger(name, rule);
    if (!value) Fail(name, rule.Text(), "nothing (the key is required)");
    return *value;
  }

  std::optional<std::string> OptionalString(std::string_view name) const {
    const toml::node* node = Node(name);
    if (node == nullptr) return std::nullopt;
    const auto* s = node->as_string();
    if (s == nullptr || s->get().empty()) Fail(name, "a non-empty string", Describe(node));
    return s->get();
  }
  std::string String(std::string_view name) const {
    const auto value = OptionalString(name);
    if (!value) Fail(name, "a non-empty string", "nothing (the key is required)");
    return *value;
  }

  /// One of `choices`; `fallback` when absent (required when fallback is empty).
  std::string Choice(std::string_view name,
                     std::initializer_list<std::string_view> choices,
                     std::string_view fallback = {}) const {
    std::string expected = "one of";
    for (const auto c : choices)
      expected += std::string(c == *choices.begin() ? " " : ", ") + "\"" + std::string(c) + "\"";
    const toml::node* node = Node(name);
    if (node == nullptr) {
      if (fallback.empty()) Fail(name, expected, "nothing (the key is required)");
      return std::string(fallback);
    }
    const auto* s = node->as_string();
    if (s == nullptr || std::find(choices.begin(), choices.end(), s->get()) == choices.end()) {
      Fail(name, expected, Describe(node));
    }
    return s->get();
  }

  std::vector<double> RealArray(std::string_view name,
                                std::size_t size,
                                const RealRule& rule) const {
    const auto* array = ArrayNode(name, size, "numbers");
    std::vector<double> out;
    for (std::size_t i = 0; i < array->size(); ++i) {
      out.push_back(RealValue(array->get(i), Full(name) + "." + std::to_string(i), rule));
    }
    return out;
  }
  /// size 0: any non-empty length.
  std::vector<long long> IntegerArray(std::string_view name,
                                      std::size_t size,
                                      const IntRule& rule) const {
    const auto* array = ArrayNode(name, size, "integers");
    std::vector<long long> out;
    for (std::size_t i = 0; i < array->size(); ++i) {
      out.push_back(IntegerValue(array->get(i), Full(name) + "." + std::to_string(i), rule));
    }
    return out;
  }

  /// size 0: any non-empty length. Each string non-empty.
  std::vector<std::string> StringArray(std::string_view name, std::size_t size) const {
    const auto* array = ArrayNode(name, size, "strings");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < array->size(); ++i) {
      const auto* v = array->get(i)->as_string();
      if (v == nullptr || v->get().empty()) {
        doc_.Fail(Full(name) + "." + std::to_string(i), "a non-empty string", Describe(array->get(i)));
      }
      out.push_back(v->get());
    }
    return out;
  }

  /// Rejects keys of this table that `type` does not use.
  void OnlyKeys(std::initializer_list<std::string_view> allowed, std::string_view why) const {
    OnlyKeys(std::vector<std::string_view>(allowed), why);
  }
  void OnlyKeys(const std::vector<std::string_view>& allowed, std::string_view why) const {
    if (table_ == nullptr) return;
    for (const auto& [name, node] : *table_) {
      if (std::find(allowed.begin(), allowed.end(), name.str()) != allowed.end()) continue;
      std::string list;
      for (const auto a : allowed) list += std::string(list.empty() ? "" : ", ") + std::string(a);
      Fail(name.str(), "only the keys " + list + " " + std::string(why),
           std::string(name.str()) + " = " + Describe(&node));
    }
  }

 private:
  const toml::array* ArrayNode(std::string_view name,
                               std::size_t size,
                               std::string_view what) const {
    const toml::node* node = Node(name);
    const std::string expected =
        size > 0 ? "an array of " + std::to_string(size) + " " + std::string(what)
                 : "a non-empty array of " + std::string(what);
    if (node == nullptr) Fail(name, expected, "nothing (the key is required)");
    const auto* array = node->as_array();
    if (array == nullptr) Fail(name, expected, Describe(node));
    if ((size > 0 && array->size() != size) || array->empty()) {
      Fail(name, expected, "an array of " + std::to_string(array->size()));
    }
    return array;
  }
  double RealValue(const toml::node* node, const std::string& key, const RealRule& rule) const {
    double value = 0.0;
    if (const auto* f = node->as_floating_point()) {
      value = f->get();
    } else if (const auto* i = node->as_integer()) {
      value = static_cast<double>(i->get());
    } else {
      doc_.Fail(key, rule.Text(), Describe(node));
    }
    if (!rule.Accepts(value)) doc_.Fail(key, rule.Text(), Describe(node));
    return value;
  }
  long long IntegerValue(const toml::node* node,
                         const std::string& key,
                         const IntRule& rule) const {
    const auto* i = node->as_integer();
    if (i == nullptr || !rule.Accepts(i->get())) doc_.Fail(key, rule.Text(), Describe(node));
    return i->get();
  }

  const CaseDocument::Impl& doc_;
  const toml::table* table_;
  std::string key_;
};

/// Longest name (sensor, label, parameter) in bytes.
inline constexpr std::size_t kMaxNameBytes = 256;

/// A name that becomes a CSV column, a JSON key and a word in messages and on
/// the terminal: at most kMaxNameBytes, without control characters (NUL, an
/// escape sequence, a line break), ',' or '"'. `key` is the name's key in `s`.
inline void CheckName(const Section& s, const std::string& key, const std::string& name) {
  if (HasControlCharacter(name) || name.size() > kMaxNameBytes ||
      name.find_first_of(",\"") != std::string::npos) {
    s.Fail(key,
           "a name of at most " + std::to_string(kMaxNameBytes) +
               " bytes without control characters, ',' or '\"'",
           TomlString(name.substr(0, 64)) + (name.size() > 64 ? " (cut at 64 bytes)" : ""));
  }
}

inline Section SubSection(const CaseDocument::Impl& doc, std::string_view name, bool required) {
  const toml::node* node = doc.root.get(name);
  if (node == nullptr && required) {
    doc.Fail(name, "a [" + std::string(name) + "] table", "nothing (the table is required)");
  }
  return Section(doc, node ? node->as_table() : nullptr, std::string(name));
}
inline std::string ResolvePath(const CaseDocument::Impl& doc, const std::string& file) {
  const std::filesystem::path p(file);
  if (p.is_absolute() || doc.base_directory.empty()) return p.lexically_normal().string();
  return (std::filesystem::path(doc.base_directory) / p).lexically_normal().string();
}

/// Reads [model], [beam], [[beam.segment]], [[mass]], [[spring]], [damping],
/// [[nonlinearity]], [initial] and [sensors] into `spec` (case_model.cpp).
void ReadStructure(const CaseDocument::Impl& doc, CaseSpec* spec);

/// Reads `node` (a beam node, default the right end) or `dof` (a 1-based model
/// dof; required for imported matrices) of section `s`: exactly one is set.
void ReadNodeOrDof(const Section& s, const CaseSpec& spec, int* node, int* dof);

/// Reads the single [force] into spec->force or the [[force]] tables (at most
/// kMaxForces) into spec->forces (case_force.cpp). After the structure and [data].
void ReadForces(const CaseDocument::Impl& doc, CaseSpec* spec);

/// Reads [base] (case_force.cpp). After the structure and [data].
BaseSpec ReadBase(const CaseDocument::Impl& doc, const CaseSpec& spec);

/// The largest element count of a beam. K of a beam (a fourth-order operator)
/// has a condition number growing as elements^4: round-off in the static
/// deflection of a uniform cantilever under a tip load (which Hermite
/// elements give exactly) is 2.1e-6 at 1000 elements, 4.8e-5 at 2000, 9e-3
/// at 10^4 (scipy's SuperLU alike), and at 3 x 10^4 the deflection was 22
/// times too large (beam_model_test).
inline constexpr int kMaxElements = 1000;

}  // namespace case_detail
}  // namespace podid
