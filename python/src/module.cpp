// podid._podid: the compiled half of the Python package (podid/__init__.py
// re-exports it). Errors: podid's std::invalid_argument becomes ValueError
// with podid's message (pybind11's standard translation).
#include <climits>
#include <stdexcept>

#include "bindings.hpp"

namespace py = pybind11;

namespace podid::python {

py::array RealArray(const py::handle& value, const char* name, int ndim) {
  const std::string expected = std::string(name) + ": expected a real " + std::to_string(ndim) +
                               "-D array (float or integer), got ";
  if (value.is_none()) throw py::type_error(expected + "None");
  py::array array = py::array::ensure(value);
  if (!array) throw py::type_error(expected + Py_TYPE(value.ptr())->tp_name);
  const char kind = array.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b') {
    throw py::type_error(expected + std::string(py::str(array.dtype())));
  }
  return array;
}

RealVector::RealVector(const py::handle& value, const char* name)
    : array([&] {
        const py::array a = RealArray(value, name, 1);
        if (a.ndim() != 1) {
          throw py::value_error(std::string(name) + ": expected a 1-D array, got a " +
                                std::to_string(a.ndim()) + "-D array of shape " +
                                std::string(py::repr(a.attr("shape"))));
        }
        return decltype(array)::ensure(a);
      }()),
      values(array.data(), array.size()) {}

int IntArgument(long long value, const char* name, const std::string& expected) {
  if (value < INT_MIN || value > INT_MAX) {
    throw py::value_error(std::string(name) + ": expected " + expected + ", got " +
                          std::to_string(value));
  }
  return static_cast<int>(value);
}

bool BoolArgument(const py::handle& value, const char* name) {
  py::detail::make_caster<bool> caster;
  if (!caster.load(value, /*convert=*/false)) {
    throw py::type_error(std::string(name) + ": expected True or False, got " +
                         Py_TYPE(value.ptr())->tp_name);
  }
  return static_cast<bool>(caster);
}

CaseDocument LoadCase(const std::string& case_, const std::vector<std::string>& set) {
  CaseDocument document = case_.find('\n') == std::string::npos
                              ? CaseDocument::Load(case_)
                              : CaseDocument::Parse(case_, "<case text>");
  for (const std::string& assignment : set) {
    const std::size_t eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw std::invalid_argument("set: expected key=value, got \"" + assignment + "\"");
    }
    document.Set(assignment.substr(0, eq), assignment.substr(eq + 1));
  }
  return document;
}

}  // namespace podid::python

PYBIND11_MODULE(_podid, m) {
  m.doc() = "podid: POD, wavelet ridges and Newmark simulation of nonlinear structures";
  podid::python::BindPod(m);
  podid::python::BindWavelet(m);
  podid::python::BindModel(m);
  podid::python::BindIdent(m);
}
