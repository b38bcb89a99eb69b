// The case reader's excitation tables: [force], [[force]] and [base]
// (docs/case-file.md). Split from case_file.cpp, which holds the schema.
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "case_internal.hpp"
#include "podid/core/io.hpp"
#include "podid/core/model_io.hpp"

namespace podid {
namespace case_detail {
namespace {

/// A time series read once per document family (force files, the [data] file).
std::shared_ptr<const TimeSeries> CachedSeries(const CaseDocument::Impl& doc,
                                               const std::string& cache_key,
                                               const std::string& key,
                                               const std::function<TimeSeries()>& read) {
  std::lock_guard<std::mutex> lock(doc.force_files->mutex);
  auto& cached = doc.force_files->files[cache_key];
  if (!cached) {
    try {
      cached = std::make_shared<const TimeSeries>(read());
    } catch (const std::exception& e) {
      doc.force_files->files.erase(cache_key);
      throw std::invalid_argument(doc.Where(key) + ": " + key + ": " + e.what());
    }
  }
  return cached;
}

std::string ChannelList(const TimeSeries& series) {
  std::string names;
  for (const auto& n : series.channel_names) names += (names.empty() ? "" : ", ") + n;
  return names.size() <= 200 ? names : names.substr(0, 200) + "...";
}

/// Reads the history a [force] or [base] table gives, in `unit` (N or
/// m/s^2): the type and its keys; `place` are the keys that say where the
/// excitation acts (node, dof or influence), allowed with every type.
ExcitationHistory ReadHistory(const CaseDocument::Impl& doc,
                              const Section& s,
                              const CaseSpec& spec,
                              const std::vector<std::string_view>& place,
                              std::string_view unit) {
  ExcitationHistory history;
  const std::string type = s.Choice("type", {"none", "harmonic", "sweep", "file", "channel"});
  if (type == "none") return history;  // other keys ignored, as for damping
  std::vector<std::string_view> allowed{"type"};
  allowed.insert(allowed.end(), place.begin(), place.end());
  const std::string gain_unit = std::string(unit) + " per unit of the column";
  if (type == "harmonic") {
    for (const char* k : {"amplitude", "frequency"}) allowed.push_back(k);
    s.OnlyKeys(allowed, "for type \"" + type + "\"");
    history.type = ForceType::kHarmonic;
    history.amplitude = s.Real("amplitude", AnyReal(unit));
    history.frequency_Hz = s.Real("frequency", Positive("Hz"));
  } else if (type == "sweep") {
    for (const char* k : {"amplitude", "start_frequency", "end_frequency"}) allowed.push_back(k);
    s.OnlyKeys(allowed, "for type \"" + type + "\"");
    history.type = ForceType::kSweep;
    history.amplitude = s.Real("amplitude", AnyReal(unit));
    history.start_frequency_Hz = s.Real("start_frequency", Positive("Hz"));
    history.end_frequency_Hz = s.Real("end_frequency", Positive("Hz"));
  } else if (type == "file") {
    for (const char* k : {"file", "column", "gain", "offset"}) allowed.push_back(k);
    s.OnlyKeys(allowed, "for type \"" + type + "\"");
    history.type = ForceType::kFile;
    history.file = s.String("file");
    history.column = s.String("column");
    history.gain = s.Real("gain", AnyReal(gain_unit), 1.0);
    history.offset = s.Real("offset", AnyReal(unit), 0.0);
    const std::string path = ResolvePath(doc, history.file);
    const auto series = CachedSeries(doc, path, s.Full("file"), [&] { return ReadCsv(path); });
    const int column = series->ChannelIndex(history.column);
    if (column < 0) {
      s.Fail("column", "a column of " + path + " (" + ChannelList(*series) + ")",
             Excerpt(history.column));
    }
    history.file_time_s = series->time_s;
    history.file_values = series->values.col(column);
  } else {
    for (const char* k : {"channel", "gain", "offset"}) allowed.push_back(k);
    s.OnlyKeys(allowed, "for type \"" + type + "\"");
    history.type = ForceType::kChannel;
    history.channel = s.String("channel");
    history.gain = s.Real("gain", AnyReal(std::string(unit) + " per unit of the channel"), 1.0);
    history.offset = s.Real("offset", AnyReal(unit), 0.0);
    const DataSpec& data = spec.data;
    if (data.file.empty()) {
      s.Fail("channel", "a [data] file to read it from (data.file, or the measured file given "
             "on the command line)", "no data.file");
    }
    DataReadOptions options;
    options.variable = data.variable;
    options.rate_Hz = data.rate_Hz;
    options.step_s = data.step_s;
    const std::string cache_key = data.file + "\n" + data.variable + "\n" +
                                  FormatReal(data.rate_Hz) + "\n" + FormatReal(data.step_s);
    const auto series = CachedSeries(doc, cache_key, "data.file",
                                     [&] { return ReadTimeSeries(data.file, options); });
    const int column = series->ChannelIndex(history.channel);
    if (column < 0) {
      s.Fail("channel", "a channel of " + data.file + " (" + ChannelList(*series) + ")",
             Excerpt(history.channel));
    }
    history.file_time_s = series->time_s;
    history.file_values = series->values.col(column);
  }
  return history;
}

ForceSpec ReadForceTable(const CaseDocument::Impl& doc, const Section& s, const CaseSpec& spec) {
  ForceSpec force;
  force.history_N = ReadHistory(doc, s, spec, {"node", "dof"}, "N");
  if (force.history_N.type != ForceType::kNone) ReadNodeOrDof(s, spec, &force.node, &force.dof);
  return force;
}

}  // namespace

void ReadForces(const CaseDocument::Impl& doc, CaseSpec* spec) {
  const toml::node* node = doc.root.get("force");
  if (node == nullptr) return;
  if (const auto* array = node->as_array()) {  // [[force]] (CheckKnown: tables only)
    if (array->size() > static_cast<std::size_t>(kMaxForces)) {
      doc.Fail("force", "at most " + std::to_string(kMaxForces) + " [[force]] tables",
               std::to_string(array->size()));
    }
    for (std::size_t i = 0; i < array->size(); ++i) {
      const Section s(doc, array->get(i)->as_table(), "force." + std::to_string(i));
      spec->forces.push_back(ReadForceTable(doc, s, *spec));
    }
    return;
  }
  spec->force = ReadForceTable(doc, SubSection(doc, "force", false), *spec);
}

BaseSpec ReadBase(const CaseDocument::Impl& doc, const CaseSpec& spec) {
  const Section s = SubSection(doc, "base", false);
  BaseSpec base;
  if (!s.present()) return base;
  const bool matrices = spec.model.type == ModelType::kMatrices;
  base.history_m_per_s2 = matrices
                              ? ReadHistory(doc, s, spec, {"influence", "influence_file"}, "m/s^2")
                              : ReadHistory(doc, s, spec, {}, "m/s^2");
  if (base.history_m_per_s2.type == ForceType::kNone) return base;
  if (!matrices) {
    // The beam's base moves its supports' w: it needs one (or springs, whose
    // other end is the base).
    if (spec.beam.left == BeamEnd::kFree && spec.beam.right == BeamEnd::kFree && spec.springs.empty()) {
      s.Fail("type", "a beam held by the base (a clamped or pinned end, or [[spring]]s)",
             "a free-free beam without springs");
    }
    return base;
  }
  const int n = spec.dofs();
  if (s.Has("influence") == s.Has("influence_file")) {
    s.Fail("influence", "either base.influence (" + std::to_string(n) +
                            " numbers) or base.influence_file for imported matrices",
           s.Has("influence") ? "both" : "nothing (one is required)");
  }
  if (s.Has("influence")) {
    const auto r = s.RealArray("influence", static_cast<std::size_t>(n), AnyReal("m per m of base motion"));
    base.influence = Eigen::Map<const Eigen::VectorXd>(r.data(), n);
    return base;
  }
  base.influence_file = s.String("influence_file");
  const std::string path = ResolvePath(doc, base.influence_file);
  Eigen::SparseMatrix<double> r;
  try {
    r = ReadMatrixMarket(path);
  } catch (const std::exception& e) {
    throw std::invalid_argument(doc.Where(s.Full("influence_file")) + ": " + s.Full("influence_file") +
                                ": " + e.what());
  }
  if (r.cols() != 1 || r.rows() != n) {
    s.Fail("influence_file",
           "a Matrix Market vector of " + std::to_string(n) + " x 1 (one entry per model dof)",
           std::to_string(r.rows()) + " x " + std::to_string(r.cols()));
  }
  base.influence = Eigen::VectorXd(r.col(0));
  return base;
}

}  // namespace case_detail
}  // namespace podid
