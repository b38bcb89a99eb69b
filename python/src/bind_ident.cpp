// podid.Objective, podid.identify, podid.landscape: objectives built from a
// case and a measured record, evaluated for several weightings at once, the
// NLopt identification and objective landscapes (docs/method.md, docs/cli.md).
#include <Python.h>
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "bindings.hpp"
#include "podid/core/case_file.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/ident/identify.hpp"
#include "podid/ident/landscape.hpp"
#include "podid/ident/measured_record.hpp"
#include "podid/ident/objective.hpp"
#include "podid/ident/progress.hpp"

namespace py = pybind11;

namespace podid::python {
namespace {

using Measured = std::variant<std::string, TimeSeries>;

// The measured record as podid identify prepares it (ident/measured_record.hpp):
// a path becomes the case's data.file, read with [data]'s options; either is
// conditioned by [data], and time.start moves to its first stamp. Notes go
// to Python's warnings, as podid prints them on stderr.
TimeSeries PrepareMeasured(CaseDocument& document, const Measured& measured) {
  std::vector<std::string> notes;
  TimeSeries data;
  if (const auto* path = std::get_if<std::string>(&measured)) {
    document.Set("data.file", TomlString(std::filesystem::absolute(*path).string()));
    data = ident::ReadMeasured(document, &notes);
  } else {
    data = ident::PrepareMeasured(document, std::get<TimeSeries>(measured), "measured", &notes);
  }
  for (const std::string& note : notes) {
    if (PyErr_WarnEx(PyExc_UserWarning, note.c_str(), 2) != 0) throw py::error_already_set();
  }
  return data;
}

// "wavelet" (a preset) or "U,S,IF" or "U,S,IF:1,1,0.5" (terms and weights).
ident::NamedObjective ParseWeighting(const std::string& text) {
  if (text == "full" || text == "time-free" || text == "wavelet") {
    return {text, ident::ObjectiveWeights::Preset(text)};
  }
  const std::size_t colon = text.find(':');
  try {
    const ident::ObjectiveWeights w =
        colon == std::string::npos
            ? ident::ObjectiveWeights::Parse(text)
            : ident::ObjectiveWeights::Parse(text.substr(0, colon), text.substr(colon + 1));
    return {text, w};
  } catch (const std::invalid_argument& e) {
    // The parser names the string's two halves terms and weights.
    throw std::invalid_argument("weightings: \"" + text + "\": " + e.what());
  }
}

// The wavelet term's wavelet (bindings.hpp's WaveletArguments: the CLI's
// options of identify and landscape), last in each signature, so that the earlier keywords keep
// their positions.
#define PODID_OBJECTIVE_WAVELET_KWARGS                                            \
  py::arg("wavelet") = "morlet", py::arg("omega0") = 6.0, py::arg("gamma") = 3.0, \
  py::arg("beta") = 20.0, py::arg("normalisation") = "amplitude",                 \
  py::arg("scale_convention") = "ridge"
#define PODID_OBJECTIVE_WAVELET_PARAMETERS                             \
  const std::string &family, double omega0, double gamma, double beta, \
      const std::string &normalisation, const std::string &convention
#define PODID_OBJECTIVE_WAVELET_ARGUMENTS \
  WaveletArguments { family, omega0, gamma, beta, normalisation, convention }

std::shared_ptr<ident::ObjectiveFunction> BuildObjective(const std::string& case_,
                                                         const Measured& measured,
                                                         const std::vector<std::string>& weightings,
                                                         const py::handle& modes,
                                                         double fmin,
                                                         double fmax,
                                                         bool raw_sigma,
                                                         const BoolObject& keep_mean,
                                                         const std::vector<std::string>& set,
                                                         const py::handle& ridge_threads,
                                                         const WaveletArguments& w) {
  ident::ObjectiveOptions options;
  options.weightings.clear();
  for (const std::string& w : weightings) {
    // The values come back by name: a second "full" silently replaced the first.
    for (const ident::NamedObjective& seen : options.weightings) {
      if (seen.name == w)
        throw std::invalid_argument("weightings: expected distinct names, got \"" + w + "\" twice");
    }
    options.weightings.push_back(ParseWeighting(w));
  }
  options.modes = IntArgument(modes, "modes", ">= 1");
  options.relative_sigma = !raw_sigma;
  options.remove_mean = !BoolArgument(keep_mean, "keep_mean");
  options.ridge.cwt.frequencies.min_frequency_Hz = fmin;
  options.ridge.cwt.frequencies.max_frequency_Hz = fmax;
  options.ridge.cwt.threads =  // the objective checks the rest
      IntArgument(ridge_threads, "ridge_threads", "1.." + ToText(wavelet::kMaxCwtThreads));
  options.ridge.cwt.wavelet = MakeWavelet(w);
  CaseDocument document = LoadCase(case_, set);
  const TimeSeries data = PrepareMeasured(document, measured);
  py::gil_scoped_release release;
  try {
    return std::make_shared<ident::ObjectiveFunction>(document, data, options);
  } catch (const std::invalid_argument& e) {
    // The options' and the IF term's messages name the library's fields and
    // the CLI's options; these are the keywords.
    std::string what = ReplaceAll(e.what(), "objective options: ridge: ", "");
    what = ReplaceAll(std::move(what), "objective options: ", "");
    what = ReplaceAll(std::move(what), "CwtOptions.threads", "ridge_threads");
    throw std::invalid_argument(PythonNames(ReplaceAll(std::move(what), "--fmin", "fmin")));
  }
}

// Parameter values from a {name: value} dict over the objective's starts.
Eigen::VectorXd ValuesFrom(const ident::ObjectiveFunction& f, const std::map<std::string, double>& given) {
  Eigen::VectorXd values = f.StartValues();
  for (const auto& [name, value] : given) {
    values[f.ParameterIndex(name, "parameter")] = value;
  }
  return values;
}

py::dict TermsDict(const ident::TermValues& t) {
  py::dict d;
  d["U"] = t.u;
  d["S"] = t.s;
  d["V"] = t.v;
  d["IF"] = t.f;
  return d;
}

// A Python callable progress(done, total) as a library callback: it runs with
// the GIL, and Ctrl-C or an exception in it stops the computation and is
// raised again in Python.
ident::ProgressCallback WrapProgress(const py::object& progress) {
  return [progress](const ident::Progress& p) {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!progress.is_none()) progress(p.done, p.total);
  };
}

}  // namespace

void BindIdent(py::module_& m) {
  py::class_<ident::ObjectiveFunction, std::shared_ptr<ident::ObjectiveFunction>>(
      m, "Objective",
      "The objective(s) of a case against a measured record: one simulation per evaluation\n"
      "gives the value of every weighting (docs/method.md).")
      .def(py::init([](const std::string& case_, const Measured& measured,
                       const std::vector<std::string>& weightings, const IntObject& modes,
                       double fmin, double fmax, const BoolObject& raw_sigma,
                       const BoolObject& keep_mean, const std::vector<std::string>& set,
                       const IntObject& ridge_threads, PODID_OBJECTIVE_WAVELET_PARAMETERS) {
             return BuildObjective(case_, measured, weightings, modes, fmin, fmax,
                                   BoolArgument(raw_sigma, "raw_sigma"), keep_mean, set,
                                   ridge_threads, PODID_OBJECTIVE_WAVELET_ARGUMENTS);
           }),
           py::arg("case"), py::arg("measured"),
           py::arg("weightings") = std::vector<std::string>{"full"}, py::arg("modes") = 1,
           py::arg("fmin") = 10.0, py::arg("fmax") = 120.0, py::arg("raw_sigma") = false,
           py::arg("keep_mean") = false, py::arg("set") = std::vector<std::string>{},
           py::arg("ridge_threads") = 1, PODID_OBJECTIVE_WAVELET_KWARGS,
           "case: a case-file path or TOML text; measured: a file path or a TimeSeries;\n"
           "weightings: presets (full, time-free, wavelet) or terms like \"U,S,IF:1,1,0.5\";\n"
           "ridge_threads: 2 runs a long record's ridge on two threads (the same values);\n"
           "wavelet: the IF term's wavelet, morlet (omega0) or morse (gamma, beta).")
      .def_property_readonly("parameter_names",
                             [](const ident::ObjectiveFunction& f) {
                               std::vector<std::string> names;
                               for (const ParameterSpec& p : f.parameters())
                                 names.push_back(p.name);
                               return names;
                             })
      .def_property_readonly("weighting_names",
                             [](const ident::ObjectiveFunction& f) {
                               std::vector<std::string> names;
                               for (const auto& w : f.options().weightings) names.push_back(w.name);
                               return names;
                             })
      .def_property_readonly("start", &ident::ObjectiveFunction::StartValues)
      .def_property_readonly("notes", &ident::ObjectiveFunction::notes)
      .def(
          "evaluate",
          [](const ident::ObjectiveFunction& f, const std::map<std::string, double>& values) {
            const Eigen::VectorXd x = ValuesFrom(f, values);
            ident::Evaluation e;
            {
              py::gil_scoped_release release;
              e = f.Evaluate(x);
            }
            py::dict out;
            py::dict by_name;
            for (std::size_t k = 0; k < e.values.size(); ++k) {
              by_name[py::str(f.options().weightings[k].name)] = e.failed() ? py::float_(NAN) : py::float_(e.values[k]);
            }
            out["values"] = by_name;
            out["terms"] = TermsDict(e.terms);
            out["failed"] = e.failed();
            out["failure"] = e.failure();
            return out;
          },
          py::arg("values") = std::map<std::string, double>{},
          "Evaluate at {name: value} (others at their start): {'values': {weighting: F}, 'terms':\n"
          "{U, S, V, IF}, 'failed': bool, 'failure': reason}. A failed point is NaN, not an "
          "error.");

  m.def(
      "identify",
      [](const std::string& case_, const Measured& measured, const std::string& objective,
         const std::map<std::string, double>& start, const IntObject& multistart,
         const std::string& algorithm, const IntObject& max_evaluations, double xtol,
         const IntObject& seed, const IntObject& modes, double fmin, double fmax,
         const IntObject& threads, const py::object& progress, const BoolObject& keep_mean,
         const std::vector<std::string>& set, const IntObject& ridge_threads,
         PODID_OBJECTIVE_WAVELET_PARAMETERS) {
        ident::IdentifyOptions options;  // the ints first: before the objective's work
        options.multistart =
            IntArgument(multistart, "multistart", "1 to " + ToText(ident::kMaxMultistart));
        options.max_evaluations = IntArgument(max_evaluations, "max_evaluations",
                                              "1 to " + ToText(ident::kMaxEvaluations));
        options.threads = IntArgument(threads, "threads", "0 to " + ToText(ident::kMaxThreads));
        options.seed = UInt64Argument(seed, "seed", "0 to 2^64 - 1");
        const auto f =
            BuildObjective(case_, measured, {objective}, modes, fmin, fmax, false, keep_mean, set,
                           ridge_threads, PODID_OBJECTIVE_WAVELET_ARGUMENTS);
        options.algorithm = ident::ParseAlgorithm(algorithm);
        options.start = ValuesFrom(*f, start);
        options.xtol_rel = xtol;
        options.progress = WrapProgress(progress);  // Ctrl-C stops it also without a callback
        ident::IdentifySummary summary;
        {
          py::gil_scoped_release release;
          summary = ident::Identify(*f, options);
        }
        py::dict parameters;
        for (int i = 0; i < f->parameter_count(); ++i) {
          parameters[py::str(f->parameters()[i].name)] = summary.parameters[i];
        }
        py::dict out;
        out["parameters"] = parameters;
        out["usable"] = summary.IsSolutionUsable();
        out["termination"] = std::string(ident::ToString(summary.termination));
        out["message"] = summary.message;
        out["objective"] = summary.objective;
        out["initial_objective"] = summary.initial_objective;
        out["final_objective"] = summary.final_objective;
        out["final_terms"] = TermsDict(summary.final_terms);
        out["evaluations"] = summary.evaluations;
        out["failed_evaluations"] = summary.failed_evaluations;
        out["wall_time_s"] = summary.wall_time_s;
        // The 95 % intervals (objective_uncertainty.hpp), by parameter name.
        // interval_notes: the bound an interval crosses (uncertainty.hpp), if any.
        py::dict intervals, standard_errors, interval_notes;
        if (summary.uncertainty.usable) {
          for (int i = 0; i < f->parameter_count(); ++i) {
            const py::str name(f->parameters()[i].name);
            intervals[name] = py::make_tuple(summary.uncertainty.lower[i], summary.uncertainty.upper[i]);
            standard_errors[name] = summary.uncertainty.standard_error[i];
            const auto k = static_cast<std::size_t>(i);
            if (k < summary.uncertainty.bound_notes.size() &&
                !summary.uncertainty.bound_notes[k].empty()) {
              interval_notes[name] = summary.uncertainty.bound_notes[k];
            }
          }
          out["correlation"] = summary.uncertainty.correlation;
        } else {
          out["correlation"] = py::none();
        }
        out["intervals"] = intervals;
        out["standard_errors"] = standard_errors;
        out["interval_notes"] = interval_notes;
        out["uncertainty"] = summary.uncertainty.message;
        out["summary"] = summary.FullReport();
        out["brief"] = summary.BriefReport();
        return out;
      },
      py::arg("case"), py::arg("measured"), py::arg("objective") = "wavelet",
      py::arg("start") = std::map<std::string, double>{}, py::arg("multistart") = 1,
      py::arg("algorithm") = "LN_BOBYQA", py::arg("max_evaluations") = 500, py::arg("xtol") = 1e-6,
      py::arg("seed") = 1, py::arg("modes") = 1, py::arg("fmin") = 10.0, py::arg("fmax") = 120.0,
      py::arg("threads") = 0, py::arg("progress") = py::none(), py::arg("keep_mean") = false,
      py::arg("set") = std::vector<std::string>{}, py::arg("ridge_threads") = 1,
      PODID_OBJECTIVE_WAVELET_KWARGS,
      "Identify the case's parameters from a measured record, as `podid identify` does.\n"
      "Returns a dict: 'parameters' {name: value}, 'usable', 'termination', 'summary' (the full\n"
      "report), objectives and counts. progress(done, total) is called after each evaluation.");

  m.def(
      "landscape",
      [](const std::string& case_, const Measured& measured, const std::string& param, double lower,
         double upper, const IntObject& points, const std::vector<std::string>& objectives,
         const std::map<std::string, double>& base, const IntObject& threads,
         const py::object& progress, const IntObject& modes, double fmin, double fmax,
         const BoolObject& keep_mean, const std::vector<std::string>& set,
         PODID_OBJECTIVE_WAVELET_PARAMETERS) {
        ident::LandscapeOptions options;  // the ints first: before the objective's work
        options.x.points =
            IntArgument(points, "points", "2 to " + ToText(ident::kMaxLandscapePoints));
        options.threads = IntArgument(threads, "threads", "0 to " + ToText(ident::kMaxThreads));
        const auto f =
            BuildObjective(case_, measured, objectives, modes, fmin, fmax, false, keep_mean, set,
                           py::int_(1), PODID_OBJECTIVE_WAVELET_ARGUMENTS);
        options.x.parameter = f->ParameterIndex(param, "param");
        options.x.lower = lower;
        options.x.upper = upper;
        options.base = ValuesFrom(*f, base);
        options.progress = WrapProgress(progress);  // Ctrl-C stops it also without a callback
        ident::LandscapeResult result;
        {
          py::gil_scoped_release release;
          result = ident::ComputeLandscape(*f, options);
        }
        py::dict values, metrics;
        for (std::size_t k = 0; k < result.names.size(); ++k) {
          values[py::str(result.names[k])] = Eigen::VectorXd(result.values[k].col(0));
          if (k < result.metrics.size()) {
            const ident::LandscapeMetrics& mk = result.metrics[k];
            py::dict d;
            d["local_minima"] = mk.local_minima;
            d["global_minimiser"] = mk.global_minimiser;
            d["global_minimum"] = mk.global_minimum;
            d["basin"] = py::make_tuple(mk.basin_lower, mk.basin_upper);
            d["basin_fraction"] = mk.basin_fraction;
            d["roughness"] = mk.roughness;
            metrics[py::str(result.names[k])] = d;
          }
        }
        py::dict out;
        out["x"] = result.x;
        out["values"] = values;
        out["metrics"] = metrics;
        out["termination"] = result.message;
        out["failed_points"] = result.failed_evaluations;
        out["wall_time_s"] = result.wall_time_s;
        return out;
      },
      py::arg("case"), py::arg("measured"), py::arg("param"), py::arg("lower"), py::arg("upper"),
      py::arg("points") = 101,
      py::arg("objectives") = std::vector<std::string>{"full", "time-free", "wavelet"},
      py::arg("base") = std::map<std::string, double>{}, py::arg("threads") = 0,
      py::arg("progress") = py::none(), py::arg("modes") = 1, py::arg("fmin") = 10.0,
      py::arg("fmax") = 120.0, py::arg("keep_mean") = false,
      py::arg("set") = std::vector<std::string>{}, PODID_OBJECTIVE_WAVELET_KWARGS,
      "Objectives over a 1-D grid of `param` (one simulation per point for all objectives): a\n"
      "dict with 'x', 'values' {objective: array (NaN where a point failed)} and 'metrics'.");
}

}  // namespace podid::python
