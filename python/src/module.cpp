// podid._podid: the compiled half of the Python package (podid/__init__.py
// re-exports it). Errors: podid's std::invalid_argument becomes ValueError
// with podid's message (pybind11's standard translation).
#include "bindings.hpp"

PYBIND11_MODULE(_podid, m) {
  m.doc() = "podid: POD, wavelet ridges and Newmark simulation of nonlinear structures";
  podid::python::BindPod(m);
  podid::python::BindWavelet(m);
  podid::python::BindModel(m);
  podid::python::BindIdent(m);
}
