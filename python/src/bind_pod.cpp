// podid.pod(X, method=...): the POD of a (sensors x samples) array.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <stdexcept>
#include <string>

#include "bindings.hpp"
#include "podid/core/error.hpp"
#include "podid/pod/pod.hpp"

namespace py = pybind11;

namespace podid::python {

void BindPod(py::module_& m) {
  py::class_<PodResult>(m, "PodResult", "The POD X = mean + U S V^T (see docs/pod.md).")
      .def_property_readonly("method", [](const PodResult& r) { return std::string(ToString(r.method)); })
      .def_readonly("singular_values", &PodResult::singular_values, "sigma (dim k), descending")
      .def_readonly("poms", &PodResult::poms, "U (sensors x k): column k is POM k+1, unit norm")
      .def_readonly("time_modes", &PodResult::time_modes, "V (samples x k), unit columns")
      .def_readonly("proper_orthogonal_values", &PodResult::proper_orthogonal_values,
                    "lambda = sigma^2 / samples (dim k)")
      .def_readonly("energy_fraction", &PodResult::energy_fraction)
      .def_readonly("cumulative_energy", &PodResult::cumulative_energy)
      .def_readonly("mean", &PodResult::mean, "the removed mean of each sensor (dim sensors)")
      .def_readonly("numerical_rank", &PodResult::numerical_rank)
      .def_readonly("message", &PodResult::message)
      .def("__repr__", [](const PodResult& r) {
        return "<podid.PodResult " + std::to_string(r.sensors) + " sensors x " +
               std::to_string(r.samples) + " samples, " + std::to_string(r.modes()) +
               " modes, method " + ToString(r.method) + ">";
      });

  m.def(
      "pod",
      [](const ArrayObject& object, const std::string& method, const IntObject& modes,
         const BoolObject& remove_mean, const BoolObject& time_modes) {
        // Any array-like (a nested list too), as the Eigen caster took it.
        const py::array array = RealArray(object, "X", 2);
        // A 1-D array would become one column: N sensors of 1 sample each.
        if (array.ndim() != 2) {
          throw py::value_error("X: expected a 2-D array (sensors x samples), got a " +
                                std::to_string(array.ndim()) +
                                "-D array (one sensor's samples: X[None, :])");
        }
        // pybind11's own conversion, kept alive here: a Fortran-ordered float64
        // array is viewed, anything else copied into the caster.
        py::detail::make_caster<Eigen::Ref<const Eigen::MatrixXd>> caster;
        if (!caster.load(array, true)) {
          throw py::type_error("X: expected a 2-D array of real numbers");
        }
        const Eigen::Ref<const Eigen::MatrixXd> x =
            py::detail::cast_op<Eigen::Ref<const Eigen::MatrixXd>>(caster);
        PodOptions options;
        options.method = ParsePodMethod(method);
        options.max_modes = IntArgument(modes, "modes", "0..min(sensors, samples)");
        options.remove_mean = BoolArgument(remove_mean, "remove_mean");
        options.compute_time_modes = BoolArgument(time_modes, "time_modes");
        py::gil_scoped_release release;
        try {
          PodSolver solver(options);
          return PodResult(solver.Compute(x));
        } catch (const std::invalid_argument& e) {
          // PodOptions.max_modes, "POD data" (an empty X) in the keywords' names.
          throw std::invalid_argument(PythonNames(ReplaceAll(e.what(), "POD data", "X")));
        }
      },
      py::arg("X"), py::arg("method") = "auto", py::arg("modes") = 0, py::arg("remove_mean") = true,
      py::arg("time_modes") = true,
      "POD of X (sensors x samples; a Fortran-ordered float64 array is used without a copy).\n"
      "method: auto, svd, direct or snapshot; modes: keep at most this many, <= min(sensors, "
      "samples)\n"
      "(0 = all).");
}

}  // namespace podid::python
