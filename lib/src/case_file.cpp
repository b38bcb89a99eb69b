#include "podid/core/case_file.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>

#include "case_internal.hpp"
#include "case_limits.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"

namespace podid {
using namespace case_detail;  // NOLINT: the reader's shared machinery
namespace {

// ---------------------------------------------------------------------------
// The schema: every key a case file may hold, in one place. Array indices are
// written "*". To add a key (e.g. for [identify]), add a row here and read it
// in ToSpec() or with CaseDocument::GetNumber().
enum class Kind {
  kTable, kTableArray, kReal, kInteger, kString, kRealArray, kIntegerArray, kStringArray,
  kTableOrArray,  ///< [force] or [[force]]: "force.key" or "force.*.key"
};

struct SchemaEntry {
  std::string_view pattern;
  Kind kind;
};

constexpr SchemaEntry kSchema[] = {
    {"model", Kind::kTable},
    {"model.type", Kind::kString},
    {"model.file", Kind::kString},
    {"model.mass", Kind::kString},
    {"model.stiffness", Kind::kString},
    {"model.damping", Kind::kString},
    {"model.labels", Kind::kStringArray},
    {"beam", Kind::kTable},
    {"beam.length", Kind::kReal},
    {"beam.elements", Kind::kInteger},
    {"beam.youngs_modulus", Kind::kReal},
    {"beam.density", Kind::kReal},
    {"beam.area", Kind::kReal},
    {"beam.width", Kind::kReal},
    {"beam.height", Kind::kReal},
    {"beam.left", Kind::kString},
    {"beam.right", Kind::kString},
    {"beam.segment", Kind::kTableArray},
    {"beam.segment.*.length", Kind::kReal},
    {"beam.segment.*.elements", Kind::kInteger},
    {"beam.segment.*.youngs_modulus", Kind::kReal},
    {"beam.segment.*.density", Kind::kReal},
    {"beam.segment.*.area", Kind::kReal},
    {"beam.segment.*.width", Kind::kReal},
    {"beam.segment.*.height", Kind::kReal},
    {"beam.segment.*.second_moment", Kind::kReal},
    {"beam.second_moment", Kind::kReal},
    {"mass", Kind::kTableArray},
    {"mass.*.node", Kind::kInteger},
    {"mass.*.mass", Kind::kReal},
    {"mass.*.inertia", Kind::kReal},
    {"spring", Kind::kTableArray},
    {"spring.*.node", Kind::kInteger},
    {"spring.*.dof", Kind::kString},
    {"spring.*.stiffness", Kind::kReal},
    {"spring.*.damping", Kind::kReal},
    {"damping", Kind::kTable},
    {"damping.type", Kind::kString},
    {"damping.modal_ratios", Kind::kRealArray},
    {"damping.modes", Kind::kIntegerArray},
    {"damping.alpha", Kind::kReal},
    {"damping.beta", Kind::kReal},
    {"nonlinearity", Kind::kTableArray},
    {"nonlinearity.*.type", Kind::kString},
    {"nonlinearity.*.node", Kind::kInteger},
    {"nonlinearity.*.nodes", Kind::kIntegerArray},
    {"nonlinearity.*.dof", Kind::kInteger},
    {"nonlinearity.*.dofs", Kind::kIntegerArray},
    {"nonlinearity.*.k1", Kind::kReal},
    {"nonlinearity.*.k2", Kind::kReal},
    {"nonlinearity.*.k3", Kind::kReal},
    {"nonlinearity.*.gap", Kind::kReal},
    {"nonlinearity.*.stiffness", Kind::kReal},
    {"nonlinearity.*.mu", Kind::kReal},
    {"nonlinearity.*.normal_force", Kind::kReal},
    {"nonlinearity.*.velocity_scale", Kind::kReal},
    {"initial", Kind::kTable},
    {"initial.static_tip_force", Kind::kReal},
    {"initial.static_force", Kind::kReal},
    {"initial.node", Kind::kInteger},
    {"initial.dof", Kind::kInteger},
    {"initial.displacement", Kind::kRealArray},
    {"initial.velocity", Kind::kRealArray},
    {"force", Kind::kTableOrArray},
    {"force.type", Kind::kString},
    {"force.node", Kind::kInteger},
    {"force.dof", Kind::kInteger},
    {"force.amplitude", Kind::kReal},
    {"force.frequency", Kind::kReal},
    {"force.start_frequency", Kind::kReal},
    {"force.end_frequency", Kind::kReal},
    {"force.file", Kind::kString},
    {"force.column", Kind::kString},
    {"force.channel", Kind::kString},
    {"force.gain", Kind::kReal},
    {"force.offset", Kind::kReal},
    {"force.*.type", Kind::kString},
    {"force.*.node", Kind::kInteger},
    {"force.*.dof", Kind::kInteger},
    {"force.*.amplitude", Kind::kReal},
    {"force.*.frequency", Kind::kReal},
    {"force.*.start_frequency", Kind::kReal},
    {"force.*.end_frequency", Kind::kReal},
    {"force.*.file", Kind::kString},
    {"force.*.column", Kind::kString},
    {"force.*.channel", Kind::kString},
    {"force.*.gain", Kind::kReal},
    {"force.*.offset", Kind::kReal},
    {"base", Kind::kTable},
    {"base.type", Kind::kString},
    {"base.amplitude", Kind::kReal},
    {"base.frequency", Kind::kReal},
    {"base.start_frequency", Kind::kReal},
    {"base.end_frequency", Kind::kReal},
    {"base.file", Kind::kString},
    {"base.column", Kind::kString},
    {"base.channel", Kind::kString},
    {"base.gain", Kind::kReal},
    {"base.offset", Kind::kReal},
    {"base.influence", Kind::kRealArray},
    {"base.influence_file", Kind::kString},
    {"time", Kind::kTable},
    {"time.duration", Kind::kReal},
    {"time.step", Kind::kReal},
    {"time.start", Kind::kReal},
    {"data", Kind::kTable},
    {"data.file", Kind::kString},
    {"data.variable", Kind::kString},
    {"data.channels", Kind::kStringArray},
    {"data.rate", Kind::kReal},
    {"data.step", Kind::kReal},
    {"data.window", Kind::kRealArray},
    {"data.detrend", Kind::kString},
    {"data.filter", Kind::kString},
    {"data.filter_order", Kind::kInteger},
    {"data.cutoff", Kind::kReal},
    {"data.band", Kind::kRealArray},
    {"data.decimate", Kind::kInteger},
    {"sensors", Kind::kTable},
    {"sensors.dof", Kind::kString},
    {"sensors.nodes", Kind::kIntegerArray},
    {"sensors.dofs", Kind::kIntegerArray},
    {"sensors.names", Kind::kStringArray},
    {"sensors.quantity", Kind::kString},
    {"sensors.reference", Kind::kString},
    {"noise", Kind::kTable},
    {"noise.relative", Kind::kReal},
    {"noise.seed", Kind::kInteger},
    {"integrator", Kind::kTable},
    {"integrator.type", Kind::kString},
    {"integrator.gamma", Kind::kReal},
    {"integrator.beta", Kind::kReal},
    {"integrator.tolerance", Kind::kReal},
    {"integrator.max_iterations", Kind::kInteger},
    {"integrator.substeps", Kind::kInteger},
    {"identify", Kind::kTable},
    {"identify.parameter", Kind::kTableArray},
    {"identify.parameter.*.name", Kind::kString},
    {"identify.parameter.*.key", Kind::kString},
    {"identify.parameter.*.scale", Kind::kReal},
    {"identify.parameter.*.start", Kind::kReal},
    {"identify.parameter.*.lower", Kind::kReal},
    {"identify.parameter.*.upper", Kind::kReal},
};

constexpr double kMaxSamples = 1e9;    // keeps TimeSpec::samples() in int
constexpr double kMaxRecordedValues = 134217728.0;  // 2^27 doubles, 1 GiB
constexpr long long kMaxIterations = 1000000;

bool IsIndex(std::string_view part) {
  return !part.empty() && part.size() <= 9 &&
         std::all_of(part.begin(), part.end(), [](char c) { return c >= '0' && c <= '9'; });
}

std::size_t ToIndex(std::string_view part) {
  std::size_t value = 0;
  std::from_chars(part.data(), part.data() + part.size(), value);
  return value;
}

std::vector<std::string_view> SplitKey(std::string_view key) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    parts.push_back(key.substr(start, dot == std::string_view::npos ? key.npos : dot - start));
    if (dot == std::string_view::npos) break;
    start = dot + 1;
  }
  return parts;
}

std::string Join(const std::vector<std::string_view>& parts, std::size_t count, bool pattern) {
  std::string out;
  for (std::size_t i = 0; i < count; ++i) {
    if (i > 0) out += '.';
    out += (pattern && IsIndex(parts[i])) ? std::string_view("*") : parts[i];
  }
  return out;
}

/// The kind of a pattern ("nonlinearity.*.k3"), including elements of value
/// arrays ("damping.modal_ratios.*"); nullopt when not in the schema.
std::optional<Kind> LookupKind(std::string_view pattern) {
  for (const auto& entry : kSchema) {
    if (entry.pattern == pattern) return entry.kind;
  }
  if (pattern.size() > 2 && pattern.substr(pattern.size() - 2) == ".*") {
    const auto parent = LookupKind(pattern.substr(0, pattern.size() - 2));
    if (parent == Kind::kRealArray) return Kind::kReal;
    if (parent == Kind::kIntegerArray) return Kind::kInteger;
    if (parent == Kind::kStringArray) return Kind::kString;
  }
  return std::nullopt;
}

/// Names allowed directly under `parent_pattern` ("" for the top level).
std::string AllowedChildren(std::string_view parent_pattern) {
  std::string out;
  for (const auto& entry : kSchema) {
    const std::string_view p = entry.pattern;
    std::string_view rest;
    if (parent_pattern.empty()) {
      rest = p;
    } else if (p.size() > parent_pattern.size() + 1 &&
               p.substr(0, parent_pattern.size()) == parent_pattern &&
               p[parent_pattern.size()] == '.') {
      rest = p.substr(parent_pattern.size() + 1);
    } else {
      continue;
    }
    if (rest.find('.') != std::string_view::npos) continue;
    if (!out.empty()) out += ", ";
    out += rest;
  }
  return out;
}

}  // namespace

// ---------------------------------------------------------------------------

std::string CaseDocument::Impl::Where(std::string_view key) const {
  // A value set from outside wins over the file's lines, for the key and for
  // any table or array that contains it.
  std::string k(key);
  while (true) {
    if (const auto it = origins.find(k); it != origins.end()) return it->second;
    const auto dot = k.rfind('.');
    if (dot == std::string::npos) break;
    k.resize(dot);
  }
  k = std::string(key);
  while (lines) {
    if (const auto it = lines->find(k); it != lines->end()) {
      return source + ":" + std::to_string(it->second);
    }
    const auto dot = k.rfind('.');
    if (dot == std::string::npos) break;
    k.resize(dot);
  }
  return source;
}

namespace {

void RecordLines(const toml::node& node, const std::string& key, std::map<std::string, int>& out) {
  const auto line = node.source().begin.line;
  if (!key.empty() && line > 0) out[key] = static_cast<int>(line);
  if (const auto* table = node.as_table()) {
    for (const auto& [name, child] : *table) {
      RecordLines(child,
                  key.empty() ? std::string(name.str()) : key + "." + std::string(name.str()), out);
    }
  } else if (const auto* array = node.as_array()) {
    for (std::size_t i = 0; i < array->size(); ++i) {
      RecordLines(*array->get(i), key + "." + std::to_string(i), out);
    }
  }
}

/// Checks that every key is in the schema and that tables and arrays of
/// tables have the right shape. Scalars are checked where they are read.
void CheckKnown(const CaseDocument::Impl& doc,
                const toml::node& node,
                const std::string& key,
                const std::string& pattern,
                Kind kind) {
  switch (kind) {
    case Kind::kTable: {
      const auto* table = node.as_table();
      if (table == nullptr) doc.Fail(key, "a table", Describe(&node));
      for (const auto& [name, child] : *table) {
        const std::string child_key =
            key.empty() ? std::string(name.str()) : key + "." + std::string(name.str());
        const std::string child_pattern =
            pattern.empty() ? std::string(name.str()) : pattern + "." + std::string(name.str());
        const auto child_kind = LookupKind(child_pattern);
        if (!child_kind || IsIndex(name.str())) {
          doc.Fail(child_key,
                   "a key of the case-file schema (here: " + AllowedChildren(pattern) + ")",
                   "an unknown key");
        }
        CheckKnown(doc, child, child_key, child_pattern, *child_kind);
      }
      break;
    }
    case Kind::kTableOrArray:
      CheckKnown(doc, node, key, pattern, node.is_array() ? Kind::kTableArray : Kind::kTable);
      break;
    case Kind::kTableArray: {
      const auto* array = node.as_array();
      if (array == nullptr || !array->is_array_of_tables()) {
        doc.Fail(key, std::string("an array of tables [[") + key + "]]", Describe(&node));
      }
      for (std::size_t i = 0; i < array->size(); ++i) {
        CheckKnown(doc, *array->get(i), key + "." + std::to_string(i), pattern + ".*",
                   Kind::kTable);
      }
      break;
    }
    default:
      break;
  }
}

// --- the sections ----------------------------------------------------------

DataSpec ReadData(const CaseDocument::Impl& doc) {
  const Section s = SubSection(doc, "data", false);
  DataSpec data;
  if (!s.present()) return data;
  if (const auto file = s.OptionalString("file")) data.file = ResolvePath(doc, *file);
  data.variable = s.OptionalString("variable").value_or("");
  if (s.Has("rate") && s.Has("step")) {
    s.Fail("step", "either data.rate or data.step, not both", "both");
  }
  data.rate_Hz = s.Real("rate", Positive("Hz"), 0.0);
  data.step_s = s.Real("step", Positive("s"), 0.0);
  // A subnormal step (1e-320 s) or rate has an infinite reciprocal (time_series.hpp).
  if (data.step_s > 0.0 && !IsSamplingStep(data.step_s)) {
    s.Fail("step", "a step whose rate 1 / step is finite (s)", FormatReal(data.step_s));
  }
  if (data.rate_Hz > 0.0 && !IsSamplingRate(data.rate_Hz)) {
    s.Fail("rate", "a rate whose step 1 / rate is finite (Hz)", FormatReal(data.rate_Hz));
  }
  ConditioningOptions& c = data.conditioning;
  if (s.Has("channels")) {
    c.channels = s.StringArray("channels", 0);
    if (c.channels.size() > 65536) {
      s.Fail("channels", "at most 65536 names", ToText(c.channels.size()) + " names");
    }
  }
  if (s.Has("window")) {
    const auto w = s.RealArray("window", 2, AnyReal("s"));
    if (!(w[0] < w[1])) {
      s.Fail("window", "[start, end] with start < end (s)",
             "[" + FormatReal(w[0]) + ", " + FormatReal(w[1]) + "]");
    }
    c.window_start_s = w[0];
    c.window_end_s = w[1];
  }
  const std::string detrend = s.Choice("detrend", {"none", "constant", "linear"}, "none");
  c.detrend = detrend == "linear" ? Detrend::kLinear
              : detrend == "constant" ? Detrend::kConstant
                                      : Detrend::kNone;
  const std::string filter =
      s.Choice("filter", {"none", "lowpass", "highpass", "bandpass"}, "none");
  const std::string why = "for filter \"" + filter + "\"";
  if (filter == "none") {
    for (const char* key : {"filter_order", "cutoff", "band"}) {
      if (s.Has(key)) s.Fail(key, "no " + std::string(key) + " without data.filter", "one");
    }
  } else {
    c.filter.order = static_cast<int>(
        s.OptionalInteger("filter_order", {1, kMaxFilterOrder}).value_or(c.filter.order));
    if (filter == "bandpass") {
      if (s.Has("cutoff")) s.Fail("cutoff", "band = [low, high] " + why, "cutoff");
      const auto band = s.RealArray("band", 2, Positive("Hz"));
      if (!(band[0] < band[1])) {
        s.Fail("band", "[low, high] with low < high (Hz)",
               "[" + FormatReal(band[0]) + ", " + FormatReal(band[1]) + "]");
      }
      c.filter.type = FilterType::kBandpass;
      c.filter.low_Hz = band[0];
      c.filter.high_Hz = band[1];
    } else {
      if (s.Has("band")) s.Fail("band", "cutoff = f (Hz) " + why, "band");
      const double cutoff = s.Real("cutoff", Positive("Hz"));
      if (filter == "lowpass") {
        c.filter.type = FilterType::kLowpass;
        c.filter.high_Hz = cutoff;
      } else {
        c.filter.type = FilterType::kHighpass;
        c.filter.low_Hz = cutoff;
      }
    }
  }
  c.decimate = static_cast<int>(s.OptionalInteger("decimate", {1, kMaxDecimation}).value_or(1));
  return data;
}

TimeSpec ReadTime(const CaseDocument::Impl& doc) {
  const Section s = SubSection(doc, "time", true);
  TimeSpec time;
  time.duration_s = s.Real("duration", Positive("s"));
  time.step_s = s.Real("step", Positive("s"));
  time.start_s = s.Real("start", AnyReal("s"), 0.0);
  if (time.step_s > time.duration_s) {
    s.Fail("step", "a step <= time.duration = " + FormatReal(time.duration_s) + " s",
           FormatReal(time.step_s));
  }
  if (time.duration_s / time.step_s > kMaxSamples) {
    s.Fail("step", "at most 1e9 steps (duration / step)",
           FormatReal(time.duration_s / time.step_s) + " steps");
  }
  return time;
}

NoiseSpec ReadNoise(const CaseDocument::Impl& doc) {
  const Section s = SubSection(doc, "noise", false);
  NoiseSpec noise;
  noise.relative = s.Real("relative", NonNegative(""), 0.0);
  noise.seed = static_cast<unsigned long long>(s.OptionalInteger("seed", {0}).value_or(1));
  return noise;
}

IntegratorSpec ReadIntegrator(const CaseDocument::Impl& doc) {
  const Section s = SubSection(doc, "integrator", false);
  IntegratorSpec integrator;
  integrator.type = s.Choice("type", {"modified", "newmark"}, "modified") == "modified"
                        ? IntegratorType::kModifiedNewmark
                        : IntegratorType::kNewmark;
  integrator.gamma = s.Real("gamma", {0.5, false, 1.0, false, ""}, integrator.gamma);
  integrator.beta = s.Real("beta", {0.0, true, 0.5, false, ""}, integrator.beta);
  integrator.tolerance = s.Real("tolerance", {0.0, true, 1.0, true, ""}, integrator.tolerance);
  integrator.max_iterations = static_cast<int>(
      s.OptionalInteger("max_iterations", {1, kMaxIterations}).value_or(integrator.max_iterations));
  integrator.substeps =
      static_cast<int>(s.OptionalInteger("substeps", {1, kMaxSubsteps}).value_or(integrator.substeps));
  return integrator;
}

/// True when every array index in `key` addresses an existing element.
bool IndicesExist(const toml::table& root, std::string_view key) {
  const toml::node* node = &root;
  for (const auto part : SplitKey(key)) {
    if (node == nullptr) return true;  // a missing table: its keys take defaults
    if (const auto* array = node->as_array()) {
      if (!IsIndex(part) || ToIndex(part) >= array->size()) return false;
      node = array->get(ToIndex(part));
    } else if (const auto* table = node->as_table()) {
      node = table->get(part);
    } else {
      return false;
    }
  }
  return true;
}

std::vector<ParameterSpec> ReadParameters(const CaseDocument::Impl& doc) {
  std::vector<ParameterSpec> out;
  const toml::node* identify = doc.root.get("identify");
  if (identify == nullptr) return out;
  const toml::node* node = identify->as_table()->get("parameter");
  if (node == nullptr) return out;
  const auto& array = *node->as_array();
  std::set<std::string> names;
  for (std::size_t i = 0; i < array.size(); ++i) {
    const Section s(doc, array.get(i)->as_table(), "identify.parameter." + std::to_string(i));
    ParameterSpec p;
    p.name = s.String("name");
    CheckName(s, "name", p.name);
    if (!names.insert(p.name).second) {
      s.Fail("name", "a name no other identify.parameter has", TomlString(p.name) + " again");
    }
    p.key = s.String("key");
    if (!CaseDocument::IsNumericKey(p.key) || !IndicesExist(doc.root, p.key)) {
      s.Fail("key",
             "a real-valued key of this case (e.g. \"nonlinearity.0.k3\", with existing array "
             "indices)",
             "\"" + p.key + "\"");
    }
    p.scale = s.Real("scale", AnyReal(""), 1.0);
    if (p.scale == 0.0) s.Fail("scale", "a number != 0", "0");
    p.lower = s.Real("lower", AnyReal(""));
    p.upper = s.Real("upper", AnyReal(""));
    if (!(p.lower < p.upper)) {
      s.Fail("upper", "a number > lower = " + FormatReal(p.lower), FormatReal(p.upper));
    }
    p.start = s.Real("start", {p.lower, false, p.upper, false, "between lower and upper"});
    out.push_back(p);
  }
  return out;
}

}  // namespace

// ---------------------------------------------------------------------------
CaseDocument::CaseDocument(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
CaseDocument::CaseDocument(const CaseDocument& other)
    : impl_(std::make_unique<Impl>(*other.impl_)) {}
CaseDocument& CaseDocument::operator=(const CaseDocument& other) {
  if (this != &other) impl_ = std::make_unique<Impl>(*other.impl_);
  return *this;
}
CaseDocument::CaseDocument(CaseDocument&& other) noexcept = default;
CaseDocument& CaseDocument::operator=(CaseDocument&& other) noexcept = default;
CaseDocument::~CaseDocument() = default;

const std::string& CaseDocument::source_name() const { return impl_->source; }

CaseDocument CaseDocument::Load(const std::string& path) {
  // At most kMaxCaseFileBytes + 1 bytes are read, also from /dev/zero or a FIFO.
  const std::string text = case_detail::ReadCaseText(path);
  std::string base = std::filesystem::path(path).parent_path().string();
  return Parse(text, path, std::move(base));
}

CaseDocument CaseDocument::Parse(std::string_view text,
                                 std::string source_name,
                                 std::string base_directory) {
  case_detail::CheckCaseText(text, source_name);  // size and nesting, before toml++
  auto impl = std::make_unique<Impl>();
  try {
    impl->root = toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    const auto& begin = e.source().begin;
    ThrowInvalid(
        source_name + ":" + std::to_string(begin.line) + ":" + std::to_string(begin.column),
        "valid TOML", std::string(e.description()));
  }
  auto lines = std::make_shared<std::map<std::string, int>>();
  RecordLines(impl->root, "", *lines);
  impl->lines = std::move(lines);
  impl->source = std::move(source_name);
  impl->base_directory = std::move(base_directory);
  impl->force_files = std::make_shared<ForceFileCache>();
  return CaseDocument(std::move(impl));
}

bool CaseDocument::IsNumericKey(std::string_view key) {
  if (key.empty()) return false;
  const auto parts = SplitKey(key);
  for (const auto p : parts) {
    if (p.empty()) return false;
  }
  return LookupKind(Join(parts, parts.size(), true)) == Kind::kReal;
}

namespace {

/// Finds or creates the container and slot for `parts` in `root`, then calls
/// assign(table*, key) or assign(array*, index) for the last part. `origin`
/// names the change in messages.
template <typename AssignInTable, typename AssignInArray>
void Navigate(toml::table& root,
              const std::vector<std::string_view>& parts,
              const std::string& origin,
              const AssignInTable& assign_in_table,
              const AssignInArray& assign_in_array) {
  toml::node* node = &root;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const bool last = i + 1 == parts.size();
    const std::string prefix = Join(parts, i + 1, false);
    if (auto* table = node->as_table()) {
      if (last) {
        assign_in_table(*table, parts[i]);
        return;
      }
      toml::node* child = table->get(parts[i]);
      if (child == nullptr) {
        auto kind = LookupKind(Join(parts, i + 1, true));
        if (kind == Kind::kTableOrArray)  // [force] or [[force]]: the next part says which
          kind = IsIndex(parts[i + 1]) ? Kind::kTableArray : Kind::kTable;
        if (kind == Kind::kTable) {
          child = table->insert_or_assign(parts[i], toml::table{}).first->second.as_table();
        } else {
          child = table->insert_or_assign(parts[i], toml::array{}).first->second.as_array();
        }
      }
      node = child;
    } else if (auto* array = node->as_array()) {
      const std::size_t index = ToIndex(parts[i]);
      if (!IsIndex(parts[i]) || index > array->size()) {
        ThrowInvalid(origin,
                     "an index <= " + std::to_string(array->size()) + " into " +
                         Join(parts, i, false) + " (which has " + std::to_string(array->size()) +
                         " elements; the next index appends)",
                     Excerpt(parts[i]));
      }
      if (last) {
        assign_in_array(*array, index);
        return;
      }
      if (index == array->size()) array->push_back(toml::table{});
      node = array->get(index);
    } else {
      ThrowInvalid(origin, "a table or an array at " + Join(parts, i, false), Describe(node));
    }
  }
}

void CheckSchemaKey(const std::vector<std::string_view>& parts,
                    std::string_view key,
                    const std::string& origin) {
  for (const auto p : parts) {
    if (p.empty()) ThrowInvalid(origin, "a dotted key such as beam.length", Excerpt(key));
  }
  if (!LookupKind(Join(parts, parts.size(), true))) {
    ThrowInvalid(origin,
                 "a key of the case-file schema (docs/case-file.md; array elements by index, "
                 "e.g. nonlinearity.0.k3)",
                 "the unknown key \"" + std::string(key) + "\"");
  }
}

}  // namespace

void CaseDocument::Set(std::string_view key, std::string_view value_text) {
  const std::string origin = "--set " + std::string(key) + "=" + std::string(value_text);
  const auto parts = SplitKey(key);
  CheckSchemaKey(parts, key, origin);
  const Kind kind = *LookupKind(Join(parts, parts.size(), true));

  case_detail::CheckCaseText(value_text, origin);
  toml::table parsed;
  bool ok = false;
  try {
    parsed = toml::parse("v = " + std::string(value_text) + "\n", origin);
    ok = parsed.size() == 1 && parsed.contains("v");
  } catch (const toml::parse_error&) {
    ok = false;
  }
  if (!ok) {
    const bool bare_word =
        !value_text.empty() && value_text.find_first_of("\"'=[]{}#\n\r") == std::string_view::npos;
    if (kind == Kind::kString && bare_word) {
      parsed = toml::table{};
      parsed.insert_or_assign("v", std::string(value_text));
    } else {
      ThrowInvalid(origin, "a TOML value (a number, \"text\", [a, b], true or false)",
                   Excerpt(value_text));
    }
  }
  toml::node& value = *parsed.get("v");
  Navigate(
      impl_->root, parts, origin,
      [&](toml::table& table, std::string_view name) {
        value.visit([&](auto&& v) { table.insert_or_assign(name, std::move(v)); });
      },
      [&](toml::array& array, std::size_t index) {
        value.visit([&](auto&& v) {
          if (index == array.size()) {
            array.push_back(std::move(v));
          } else {
            array.replace(array.cbegin() + static_cast<std::ptrdiff_t>(index), std::move(v));
          }
        });
      });
  impl_->origins[std::string(key)] = origin;
}

void CaseDocument::SetNumber(std::string_view key, double value) {
  if (!IsNumericKey(key)) {
    ThrowInvalid("SetNumber(" + std::string(key) + ")", "a real-valued key of the case-file schema",
                 Excerpt(key));
  }
  const auto parts = SplitKey(key);
  auto it = impl_->origins.find(key);
  if (it == impl_->origins.end()) {
    it = impl_->origins
             .emplace(std::string(key),
                      impl_->source + " (" + std::string(key) + " set by the program)")
             .first;
  }
  Navigate(
      impl_->root, parts, it->second,
      [&](toml::table& table, std::string_view name) {
        if (auto* f = table.get_as<double>(name)) {
          *f = value;  // the common case: no allocation
        } else {
          table.insert_or_assign(name, value);
        }
      },
      [&](toml::array& array, std::size_t index) {
        if (index == array.size()) {
          array.push_back(value);
        } else if (auto* f = array.get_as<double>(index)) {
          *f = value;
        } else {
          array.replace(array.cbegin() + static_cast<std::ptrdiff_t>(index), value);
        }
      });
}

namespace {
const toml::node* Find(const toml::table& root, std::string_view key) {
  const toml::node* node = &root;
  for (const auto part : SplitKey(key)) {
    if (const auto* table = node->as_table()) {
      node = table->get(part);
    } else if (const auto* array = node->as_array()) {
      node = IsIndex(part) ? array->get(ToIndex(part)) : nullptr;
    } else {
      node = nullptr;
    }
    if (node == nullptr) return nullptr;
  }
  return node;
}
}  // namespace

bool CaseDocument::Has(std::string_view key) const { return Find(impl_->root, key) != nullptr; }

double CaseDocument::GetNumber(std::string_view key) const {
  const toml::node* node = Find(impl_->root, key);
  if (node != nullptr) {
    if (const auto* f = node->as_floating_point()) return f->get();
    if (const auto* i = node->as_integer()) return static_cast<double>(i->get());
  }
  impl_->Fail(key, "a number", Describe(node));
}

namespace {
/// Everything but [identify]: the model, its start, its time and its output.
CaseSpec ReadModel(const CaseDocument::Impl& doc) {
  CheckKnown(doc, doc.root, "", "", Kind::kTable);
  CaseSpec spec;
  spec.source = doc.source;
  ReadStructure(doc, &spec);
  spec.data = ReadData(doc);
  ReadForces(doc, &spec);
  spec.base = ReadBase(doc, spec);
  spec.time = ReadTime(doc);
  // The simulated record, (duration / step + 1) samples x sensors doubles,
  // must fit in memory: the data files' bound of 2^27 values (1 GiB).
  const double recorded = (spec.time.duration_s / spec.time.step_s + 1.0) *
                          static_cast<double>(spec.sensors.ChannelNames().size());
  if (recorded > kMaxRecordedValues) {
    doc.Fail("time.step",
             "at most 134217728 recorded values ((duration / step + 1) x sensor channels)",
             FormatReal(recorded) + " values");
  }
  spec.noise = ReadNoise(doc);
  spec.integrator = ReadIntegrator(doc);
  return spec;
}
}  // namespace

CaseSpec CaseDocument::ToSpec() const {
  CaseSpec spec = ReadModel(*impl_);
  spec.parameters = ReadParameters(*impl_);
  // A parameter whose key is absent from the file must be one this case can
  // take (nonlinearity.0.gap is no use to a cubic element): try it at start.
  for (std::size_t i = 0; i < spec.parameters.size(); ++i) {
    const ParameterSpec& p = spec.parameters[i];
    if (Has(p.key)) continue;
    CaseDocument trial(*this);
    trial.SetNumber(p.key, p.scale * p.start);
    try {
      (void)ReadModel(*trial.impl_);
    } catch (const std::invalid_argument& e) {
      impl_->Fail("identify.parameter." + std::to_string(i) + ".key",
                  "a key this case can take at scale * start (setting it gives: " +
                      std::string(e.what()) + ")",
                  "\"" + p.key + "\"");
    }
  }
  return spec;
}

std::vector<std::pair<std::string, std::string>> ParseSetArguments(
    const std::vector<std::string>& arguments) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& argument : arguments) {
    const auto eq = argument.find('=');
    if (eq == std::string::npos || eq == 0) {
      ThrowInvalid("--set " + argument, "key=value (e.g. time.duration=1.0)",
                   "\"" + argument + "\"");
    }
    auto trim = [](std::string s) {
      const auto b = s.find_first_not_of(" \t");
      const auto e = s.find_last_not_of(" \t");
      return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
    };
    std::string key = trim(argument.substr(0, eq));
    if (key.empty()) {
      ThrowInvalid("--set " + argument, "key=value (e.g. time.duration=1.0)",
                   "\"" + argument + "\"");
    }
    out.emplace_back(std::move(key), trim(argument.substr(eq + 1)));
  }
  return out;
}

void ApplySetArguments(CaseDocument& document, const std::vector<std::string>& arguments) {
  for (const auto& [key, value] : ParseSetArguments(arguments)) document.Set(key, value);
}

std::string TomlString(std::string_view text) {
  std::string out = "\"";
  for (const unsigned char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c == 0x7f) {
      char buffer[8];
      std::snprintf(buffer, sizeof(buffer), "\\u%04x", c);
      out += buffer;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

}  // namespace podid
