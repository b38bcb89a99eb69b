// podid._podid: the compiled half of the Python package (podid/__init__.py
// re-exports it). Errors: podid's std::invalid_argument becomes ValueError
// with podid's message (pybind11's standard translation).
#include <climits>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>

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

namespace {

// The int an int keyword holds, as operator.index gives it; py::type_error
// naming `name` for anything else (a float, None, a string).
py::int_ IntOf(const py::handle& value, const char* name) {
  // numpy.bool_ has an __index__ that NumPy 1.x deprecates and NumPy 2
  // refuses: not an integer type (np.issubdtype(np.bool_, np.integer) is False).
  const std::string_view type = Py_TYPE(value.ptr())->tp_name;
  if (PyIndex_Check(value.ptr()) == 0 || type == "numpy.bool_" || type == "numpy.bool") {
    throw py::type_error(std::string(name) + ": expected an int, got " + std::string(type));
  }
  PyObject* const index = PyNumber_Index(value.ptr());
  if (index == nullptr) throw py::error_already_set();
  return py::reinterpret_steal<py::int_>(index);
}

[[noreturn]] void ThrowOutOfRange(const char* name,
                                  const std::string& expected,
                                  const std::string& got) {
  throw py::value_error(std::string(name) + ": expected " + expected + ", got " + got);
}

}  // namespace

long long Int64Argument(const py::handle& value, const char* name, const std::string& expected) {
  const py::int_ index = IntOf(value, name);
  int overflow = 0;
  const long long result = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (result == -1 && PyErr_Occurred() != nullptr) throw py::error_already_set();
  if (overflow != 0) ThrowOutOfRange(name, expected, std::string(py::repr(index)));
  return result;
}

int IntArgument(const py::handle& value, const char* name, const std::string& expected) {
  const long long result = Int64Argument(value, name, expected);
  if (result < INT_MIN || result > INT_MAX) ThrowOutOfRange(name, expected, std::to_string(result));
  return static_cast<int>(result);
}

std::uint64_t UInt64Argument(const py::handle& value,
                             const char* name,
                             const std::string& expected) {
  const py::int_ index = IntOf(value, name);
  const unsigned long long result = PyLong_AsUnsignedLongLong(index.ptr());
  if (result == std::numeric_limits<unsigned long long>::max() && PyErr_Occurred() != nullptr) {
    // OverflowError: negative or beyond 2^64 - 1.
    if (PyErr_ExceptionMatches(PyExc_OverflowError) == 0) throw py::error_already_set();
    PyErr_Clear();
    ThrowOutOfRange(name, expected, std::string(py::repr(index)));
  }
  return result;
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
