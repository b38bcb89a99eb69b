#pragma once
// The pieces of the `podid._podid` extension, one file per podid module.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "podid/core/case_file.hpp"
#include "podid/wavelet/cwt.hpp"

namespace podid::python {

void BindPod(pybind11::module_& m);
void BindWavelet(pybind11::module_& m);
void BindModel(pybind11::module_& m);
void BindIdent(pybind11::module_& m);

/// The library's field names in a message (FrequencyGrid.min_frequency_Hz,
/// MorletWavelet.beta) as the module's keyword arguments (fmin, beta), which
/// the caller typed (bind_wavelet.cpp).
std::string PythonNames(std::string message);

/// The wavelet's keywords (the CLI's --wavelet, --omega0, --gamma, --beta,
/// --normalisation, --scale-convention), shared by the wavelet functions and
/// the objective's IF term.
struct WaveletArguments {
  std::string family;
  double omega0, gamma, beta;
  std::string normalisation, convention;
};

/// The wavelet they name; throws std::invalid_argument (a ValueError) in
/// the keywords' names: an unknown name, or what MorletWavelet::IsValid
/// refuses (bind_wavelet.cpp).
wavelet::MorletWavelet MakeWavelet(const WaveletArguments& w);

/// Any object, for an argument the function checks itself (RealArray,
/// BoolArgument, IntArgument) to name it in its errors; typed for help()'s
/// signatures.
inline bool AnyObject(PyObject*) { return true; }
struct ArrayObject : pybind11::object {
  PYBIND11_OBJECT_DEFAULT(ArrayObject, pybind11::object, AnyObject)
};
struct BoolObject : pybind11::object {
  PYBIND11_OBJECT_DEFAULT(BoolObject, pybind11::object, AnyObject)
};
struct IntObject : pybind11::object {
  PYBIND11_OBJECT_DEFAULT(IntObject, pybind11::object, AnyObject)
};
/// An int keyword whose None means "not given" (cwt's bins).
struct OptionalIntObject : pybind11::object {
  PYBIND11_OBJECT_DEFAULT(OptionalIntObject, pybind11::object, AnyObject)
};

/// A real array argument (float, integer or bool, any array-like) as an
/// array; py::type_error naming `name` and `ndim`, the dimension the caller
/// checks, otherwise (None, complex, object): pybind11's converting Eigen
/// caster kept a complex array's real part.
pybind11::array RealArray(const pybind11::handle& value, const char* name, int ndim);

/// A real 1-D array argument as float64: a view of a contiguous float64
/// array, else a copy it keeps. py::value_error for another dimension.
struct RealVector {
  RealVector(const pybind11::handle& value, const char* name);
  pybind11::array_t<double, pybind11::array::c_style | pybind11::array::forcecast> array;
  Eigen::Map<const Eigen::VectorXd> values;
};

/// An int keyword (an IntObject: pybind11's int refused 2**31, 2**63, 1.5 and
/// None without naming it). Ints are what operator.index takes: int, bool,
/// NumPy's integers; not numpy.bool_ nor a float, even an integral one
/// (2.0), nor None: py::type_error "name: expected an int, got float".
/// Outside the C++ type, py::value_error "name: expected `expected`, got
/// value"; the library checks the rest of the range.
int IntArgument(const pybind11::handle& value, const char* name, const std::string& expected);
long long Int64Argument(const pybind11::handle& value,
                        const char* name,
                        const std::string& expected);
std::uint64_t UInt64Argument(const pybind11::handle& value,
                             const char* name,
                             const std::string& expected);

/// A bool keyword: True, False or numpy.bool_ only, py::type_error naming
/// `name` otherwise (pybind11's conversion took None as False, nan as True).
bool BoolArgument(const pybind11::handle& value, const char* name);

/// A case-file path, or TOML text when `case_` holds a newline, with
/// `--set`-style "key=value" overrides (module.cpp).
CaseDocument LoadCase(const std::string& case_, const std::vector<std::string>& set);

}  // namespace podid::python

template <>
struct pybind11::detail::handle_type_name<podid::python::ArrayObject> {
  static constexpr auto name = const_name("numpy.ndarray");
};
template <>
struct pybind11::detail::handle_type_name<podid::python::BoolObject> {
  static constexpr auto name = const_name("bool");
};
template <>
struct pybind11::detail::handle_type_name<podid::python::IntObject> {
  static constexpr auto name = const_name("int");
};
template <>
struct pybind11::detail::handle_type_name<podid::python::OptionalIntObject> {
  static constexpr auto name = const_name("Optional[int]");
};
