// podid.pod(X, method=...): the POD of a (sensors x samples) array.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <string>

#include "bindings.hpp"
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
      [](const Eigen::Ref<const Eigen::MatrixXd>& x, const std::string& method, int modes,
         bool remove_mean, bool time_modes) {
        PodOptions options;
        options.method = ParsePodMethod(method);
        options.max_modes = modes;
        options.remove_mean = remove_mean;
        options.compute_time_modes = time_modes;
        py::gil_scoped_release release;
        PodSolver solver(options);
        return PodResult(solver.Compute(x));
      },
      py::arg("X"), py::arg("method") = "auto", py::arg("modes") = 0, py::arg("remove_mean") = true,
      py::arg("time_modes") = true,
      "POD of X (sensors x samples; a Fortran-ordered float64 array is used without a copy).\n"
      "method: auto, svd, direct or snapshot; modes: keep at most this many, <= min(sensors, "
      "samples)\n"
      "(0 = all).");
}

}  // namespace podid::python
