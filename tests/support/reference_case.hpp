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

/// knl of the reference data (README: measured_knl50_*), and the acceptance
/// bound of its identification (issue 5; issue 13 for several modes): 0.5 %.
inline constexpr double kTrueKnl = 50.0;
inline constexpr double kKnlRelativeTolerance = 0.005;

}  // namespace podid::testing
