// podid.read(path, ...), podid.simulate(case, ...): recordings and the Newmark
// simulation of a case file (docs/case-file.md, docs/data-files.md).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "podid/core/case_file.hpp"
#include "podid/core/error.hpp"
#include "podid/core/io.hpp"
#include "podid/core/simulate.hpp"
#include "podid/core/time_series.hpp"

namespace py = pybind11;

namespace podid::python {

void BindModel(py::module_& m) {
  py::class_<TimeSeries>(m, "TimeSeries", "Uniformly sampled named channels (samples x channels).")
      .def_readonly("time_s", &TimeSeries::time_s)
      .def_readonly("values", &TimeSeries::values, "(samples x channels)")
      .def_readonly("channel_names", &TimeSeries::channel_names)
      .def_readonly("units", &TimeSeries::units)
      .def_property_readonly("step_s", &TimeSeries::step_s)
      .def_property_readonly("X", &TimeSeries::SnapshotMatrix,
                             "the paper's snapshot matrix (channels x samples)")
      .def("__repr__", [](const TimeSeries& s) {
        return "<podid.TimeSeries " + std::to_string(s.samples()) + " samples x " +
               std::to_string(s.channels()) + " channels>";
      });

  py::class_<SimulationResult>(m, "SimulationResult")
      .def_readonly("sensors", &SimulationResult::sensors)
      .def_property_readonly("completed",
                             [](const SimulationResult& r) { return r.summary.IsSolutionUsable(); })
      .def_property_readonly("termination",
                             [](const SimulationResult& r) { return std::string(ToString(r.summary.termination)); })
      .def_property_readonly("message", [](const SimulationResult& r) { return r.summary.message; })
      .def_property_readonly("newton_iterations",
                             [](const SimulationResult& r) { return r.summary.newton_iterations; })
      .def_property_readonly("report", [](const SimulationResult& r) { return r.summary.FullReport(); });

  m.def(
      "read",
      [](const std::string& path, const std::string& variable, const std::vector<std::string>& channels,
         double rate_Hz, double step_s) {
        DataReadOptions options;
        options.variable = variable;
        options.channels = channels;
        options.rate_Hz = rate_Hz;
        options.step_s = step_s;
        options.Check();
        // Notes (a skipped UFF data set, say) become UserWarnings, as podid
        // prints them on stderr.
        std::vector<std::string> notes;
        TimeSeries series;
        try {
          py::gil_scoped_release release;
          series = ReadTimeSeries(path, options, &notes);
        } catch (const std::invalid_argument& e) {
          // The readers name the CLI's options for a file without time (the
          // whole phrase: a path may hold "--rate").
          throw std::invalid_argument(
              ReplaceAll(e.what(), "(--rate, --step)", "(rate_Hz, step_s)"));
        }
        for (const std::string& note : notes) {
          if (PyErr_WarnEx(PyExc_UserWarning, note.c_str(), 2) != 0) throw py::error_already_set();
        }
        return series;
      },
      py::arg("path"), py::arg("variable") = "", py::arg("channels") = std::vector<std::string>{},
      py::arg("rate_Hz") = 0.0, py::arg("step_s") = 0.0,
      "Reads a CSV, .mat (v5, v7.3, test-system structs) or UFF58 file (docs/data-files.md).");

  m.def(
      "simulate",
      [](const std::string& case_, const std::vector<std::string>& set, const BoolObject& noise) {
        const CaseSpec spec = LoadCase(case_, set).ToSpec();
        SimulateOptions options;
        options.add_noise = BoolArgument(noise, "noise");
        py::gil_scoped_release release;
        return Simulate(spec, options);
      },
      py::arg("case"), py::arg("set") = std::vector<std::string>{}, py::arg("noise") = true,
      "Simulates a case (a path, or TOML text) with `set` overrides like "
      "[\"nonlinearity.0.k3=2e9\"].\n"
      "A diverging simulation is not an error: see .completed and .message.");
}

}  // namespace podid::python
