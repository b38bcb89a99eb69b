// podid._podid: the compiled half of the Python package (podid/__init__.py
// re-exports it). Errors: podid's std::invalid_argument becomes ValueError
// with podid's message (pybind11's standard translation).
#include "bindings.hpp"

#include <stdexcept>

namespace podid::python {

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
