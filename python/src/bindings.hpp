#pragma once
// The pieces of the `podid._podid` extension, one file per podid module.
#include <pybind11/pybind11.h>

namespace podid::python {

void BindPod(pybind11::module_& m);
void BindWavelet(pybind11::module_& m);
void BindModel(pybind11::module_& m);
void BindIdent(pybind11::module_& m);

}  // namespace podid::python
