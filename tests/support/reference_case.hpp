#pragma once
// The reference case (examples/beam.toml, a copy of ../shared/reference/beam.toml)
// and the reference data (tests/data/, see its README).

#include <string>
#include <vector>

#include "podid/core/case_file.hpp"
#include "podid/core/case_spec.hpp"
#include "podid/core/io.hpp"
#include "test_support.hpp"

namespace podid::testing {

/// The document of examples/beam.toml with optional `key=value` overrides (--set).
inline CaseDocument ReferenceDocument(const std::vector<std::string>& overrides = {}) {
  CaseDocument document = CaseDocument::Load(ExamplePath("beam.toml"));
  ApplySetArguments(document, overrides);
  return document;
}

/// examples/beam.toml with optional `key=value` overrides.
inline CaseSpec ReferenceCase(const std::vector<std::string>& overrides = {}) {
  return ReferenceDocument(overrides).ToSpec();
}

inline TimeSeries ReferenceData(const std::string& name) { return ReadCsv(DataPath(name)); }

}  // namespace podid::testing
